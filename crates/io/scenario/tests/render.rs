//! `[output] render`: the 3D views a run asks for, read, checked and written back.

use spraysim_scenario::{ParticleColoring, RenderCamera, RenderParams, RenderTime, Scenario, ViewPreset};

fn with_render(table: &str) -> Result<Scenario, String> {
    // `[output]` is the default scene's last table: a key or a sub-table goes at the end.
    let text = format!("{}\n{table}\n", spraysim_scenario::DEFAULT_SCENE);
    Scenario::from_toml(&text, "scene.toml").map_err(|e| e.to_string())
}

#[test]
fn render_is_off_by_default_and_true_takes_the_defaults_of_the_process() {
    assert_eq!(Scenario::default_scene().output().render, None);
    let sc = with_render("render = true").expect("valid");
    assert_eq!(sc.output().render, Some(RenderParams::defaults(sc.process().preset)));
    let r = sc.output().render.as_ref().expect("on");
    assert_eq!((r.at.as_slice(), r.size, r.point_size), (&[RenderTime::End][..], [1280, 720], 3.0));
    assert_eq!(with_render("render = false").expect("valid").output().render, None);
    let painting = sc.with_assignment("process.preset=painting").expect("valid");
    assert_eq!(painting.output().render.as_ref().map(|r| r.point_size), Some(1.0));
}

#[test]
fn a_render_table_is_read_and_written_back_the_same() {
    let sc = with_render(
        "[output.render]\nat = [0.5, \"end\", 1]\nframes = 20\neye = [-3.0, -2.0, 2.0]\ntarget = [0.0, 0.0, 1.0]\n\
         fov = 30\nsize = [640, 400]\ncolor_by = \"speed\"\npoint_size = 2.5\nexaggeration = 5\nmax_particles = 1000",
    )
    .expect("valid");
    let r = sc.output().render.clone().expect("on");
    assert_eq!(r.at, [RenderTime::At(0.5), RenderTime::End, RenderTime::At(1.0)]);
    assert_eq!(r.camera, RenderCamera::Custom { eye: [-3.0, -2.0, 2.0], target: [0.0, 0.0, 1.0] });
    assert_eq!((r.frames, r.fov, r.size, r.color_by), (20, 30.0, [640, 400], ParticleColoring::Speed));
    assert_eq!((r.point_size, r.exaggeration, r.max_particles), (2.5, 5.0, 1000));
    let again = Scenario::from_toml(&sc.to_toml(), "resolved").expect("the resolved scenario reads back");
    assert_eq!(again, sc);
    let preset = with_render("[output.render]\ncamera = \"top\"").expect("valid");
    let back = Scenario::from_toml(&preset.to_toml(), "resolved").expect("reads back");
    assert_eq!(back.output().render.as_ref().map(|r| r.camera), Some(RenderCamera::Preset(ViewPreset::Top)));
    // An override reaches into the table.
    let sc = Scenario::default_scene().with_assignment("output.render.frames=4").expect("valid");
    assert_eq!(sc.output().render.as_ref().map(|r| r.frames), Some(4));
}

#[test]
fn bad_render_settings_are_refused_naming_the_key() {
    for (table, key, says) in [
        ("render = 3", "output.render", "true or false"),
        ("[output.render]\nat = [5.0]", "output.render.at", "within the run"),
        ("[output.render]\nat = [\"later\"]", "output.render.at", "\"end\""),
        ("[output.render]\nat = []", "output.render.at", "between 1 and"),
        ("[output.render]\ncamera = \"below\"", "output.render.camera", "must be one of"),
        (
            "[output.render]\ncamera = \"top\"\neye = [1.0, 0.0, 0.0]\ntarget = [0.0, 0.0, 0.0]",
            "output.render.camera",
            "one or the other",
        ),
        ("[output.render]\neye = [1.0, 0.0, 0.0]", "output.render.target", "is required"),
        ("[output.render]\neye = [1.0, 0.0, 0.0]\ntarget = [1.0, 0.0, 0.0]", "output.render.eye", "differ"),
        ("[output.render]\nsize = [8, 100]", "output.render.size", "between 16 and 8192"),
        ("[output.render]\nsize = [100.5, 100]", "output.render.size", "whole"),
        ("[output.render]\nfov = 180", "output.render.fov", "between 1 and 170"),
        ("[output.render]\npoint_size = 0.5", "output.render.point_size", "between 1 and 64"),
        ("[output.render]\nframes = -1", "output.render.frames", "between 0 and 10000"),
        ("[output.render]\nwidth = 3", "output.render.width", "is not a key"),
    ] {
        let err = with_render(table).expect_err(table);
        assert!(err.contains(&format!("`{key}`")) && err.contains(says), "{table}: {err}");
    }
}
