//! What the GPU backend refuses, naming the feature and its key, before a run starts.

use spraysim_gpu::check;
use spraysim_scenario::Scenario;
use spraysim_scenario::scenes::{NOZZLE_AT_WALL, scenario, wall};

fn refusal(sc: &Scenario) -> String {
    match check(&sc.config()) {
        Ok(()) => panic!("the GPU backend accepted a scenario outside its scope"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn the_default_scene_the_processes_erosion_openings_and_shells_lie_in_scope() {
    assert_eq!(check(&Scenario::default_scene().config()), Ok(()));
    for preset in ["painting", "blasting"] {
        let other = Scenario::default_scene().with("process.preset", preset).expect("valid");
        assert_eq!(check(&other.config()), Ok(()), "{preset}");
    }
    let oka = Scenario::default_scene().with("process.erosion.model", "oka").expect("valid");
    assert_eq!(check(&oka.config()), Ok(()));
    let window = wall().with("[[target.opening]]\ncenter = [0.0, 0.0]\nsize = [0.4, 0.4]");
    assert_eq!(check(&scenario(&format!("{NOZZLE_AT_WALL}{window}"), "a window").config()), Ok(()));
    let pipe = "[[target]]\nname = \"pipe\"\nshape = \"cylinder\"\ncenter = [0.5, 0.0, 1.0]\n\
                axis = [0.0, 0.0, 1.0]\nradius = 0.3\nlength = 1.0\nside = \"outside\"\n";
    assert_eq!(check(&scenario(pipe, "a pipe").config()), Ok(()));
}

#[test]
fn features_outside_the_scope_are_refused_by_name_and_key() {
    let cases: [(Scenario, &str, &str); 2] = [
        (
            Scenario::default_scene().with("output.impact_log", 0.5).expect("valid"),
            "impact log",
            "output.impact_log",
        ),
        (
            Scenario::default_scene()
                .with_all(&[
                    ("process.preset".into(), "painting".into()),
                    ("process.gun".into(), "hvlp".into()),
                ])
                .expect("valid"),
            "the gun's air",
            "air.model",
        ),
    ];
    for (sc, feature, key) in cases {
        let message = refusal(&sc);
        assert!(message.contains(feature) && message.contains(key), "{message}");
        assert!(message.contains("CPU backend"), "{message}");
    }
}

/// An erosion law the engine knows only by its volumes.
#[derive(Debug)]
struct Sandpaper;

impl spraysim_engine::process::ErosionLaw for Sandpaper {
    fn removed_volume(&self, mass: f64, _speed: f64, _gamma: f64) -> f64 {
        1e-6 * mass
    }
}

#[test]
fn an_erosion_law_defined_outside_the_engine_is_refused_by_name() {
    let mut config = Scenario::default_scene().with("process.preset", "blasting").expect("valid").config();
    let erosion = config.targets[0].erosion.as_mut().expect("blasting wears the wall");
    erosion.substrate_law = std::sync::Arc::new(Sandpaper);
    let message = check(&config).map(|()| String::new()).unwrap_or_else(|e| e.to_string());
    assert!(
        message.contains("erosion laws defined outside the engine (the substrate's)")
            && message.contains("target[0] `wall`.erosion"),
        "{message}"
    );
}

#[test]
fn a_mesh_target_is_refused_by_name() {
    use glam::DVec3;
    use spraysim_engine::collision::Triangle;
    use spraysim_engine::deposit::{MeshSurface, Surface};
    let mut config = Scenario::default_scene().config();
    let triangle =
        Triangle::new(DVec3::new(0.0, -1.0, 0.0), DVec3::new(0.0, 1.0, 0.0), DVec3::new(0.0, 0.0, 2.0))
            .expect("a triangle");
    config.targets[0].surface = Surface::Mesh(MeshSurface::new(vec![triangle]).expect("a mesh"));
    let message = check(&config).map(|()| String::new()).unwrap_or_else(|e| e.to_string());
    assert!(message.contains("mesh targets") && message.contains("target[0] `wall`.mesh"), "{message}");
}
