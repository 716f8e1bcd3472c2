//! `[process] gun`, `[process] volume_solids`, `[emitter] droplets` and `[air]`: what a gun
//! sets, what is refused (naming the key and the line), and what resolves back to itself.

use spraysim_scenario::scenes::{refusal, scenario, wall_scene};
use spraysim_scenario::{AirParams, DropletsLaw, Gun, Scenario, ScenarioError};

/// The wall scene the tests change, painted.
fn painting(lines: &str) -> String {
    format!("[process]\npreset = \"painting\"\n{lines}\n{}", wall_scene(0.05, 32))
}

#[test]
fn a_gun_sets_its_spray_droplets_air_and_window() {
    for gun in Gun::ALL {
        let sc = scenario(&painting(&format!("gun = \"{}\"", gun.name())), gun.name());
        assert_eq!(sc.process().gun, Some(gun));
        let AirParams::Jet(jet) = sc.air() else { panic!("{gun:?}: a gun blows air") };
        assert!(jet.speed > 0.0 && jet.outlet_diameter > 0.0, "{gun:?}");
        assert!(!matches!(sc.emitter().droplets, DropletsLaw::None), "{gun:?}: a gun sets its droplet sizes");
        let [lo, hi] = sc.process().window.standoff;
        assert!(lo < gun.standoff() && gun.standoff() < hi);
        // Its resolved form reads back to the same scenario.
        let again = Scenario::from_toml(&sc.to_toml(), "resolved").unwrap_or_else(|e| panic!("{gun:?}: {e}"));
        assert_eq!(again, sc, "{gun:?}");
    }
    // Without a gun the painting preset is the paper's: still air, no sizes.
    let paper = scenario(&painting(""), "paper");
    assert_eq!(paper.air(), &AirParams::None);
    assert_eq!(paper.emitter().droplets, DropletsLaw::None);
}

/// An air-atomised gun's droplets get finer as its air gets faster (D₃₂ ∝ 1/U₀), unless the
/// file sets their size; an airless gun's do not follow its (entrained) air.
#[test]
fn faster_atomising_air_makes_finer_droplets() {
    let d32 = |lines: &str| match scenario(&painting(lines), "gun").emitter().droplets.clone() {
        DropletsLaw::LogNormal { sauter_mean, .. } | DropletsLaw::RosinRammler { sauter_mean, .. } => {
            sauter_mean
        }
        other => panic!("{other:?}"),
    };
    let nominal = d32("gun = \"air\"");
    let faster = d32("gun = \"air\"\n[air]\nspeed = 500.0");
    assert!((faster / nominal - 0.5).abs() < 1e-12, "{nominal} → {faster}");
    let given = d32("gun = \"air\"\n[emitter]\nsauter_mean = 3e-5\n[air]\nspeed = 500.0");
    assert_eq!(given, 3e-5);
    let airless = d32("gun = \"airless\"");
    assert_eq!(d32("gun = \"airless\"\n[air]\nspeed = 30.0"), airless);
}

#[test]
fn impossible_painting_settings_are_refused_with_their_key_and_line() {
    let refuse = |text: &str, key: &str, says: &str| {
        let (k, m) = refusal(Scenario::from_toml(text, "paint.toml"), text);
        assert_eq!(k, key, "{text}");
        assert!(m.contains(says), "{key}: {m}");
    };
    let shotcrete = format!("[process]\ngun = \"hvlp\"\n{}", wall_scene(0.05, 32));
    refuse(&shotcrete, "process.gun", "preset = \"painting\"");
    refuse(&painting("gun = \"spray_can\""), "process.gun", "\"hvlp\"");
    refuse(&painting("volume_solids = 1.5"), "process.volume_solids", "");
    refuse(&painting("volume_solids = 0.0"), "process.volume_solids", "");
    refuse(&painting("[air]\nmodel = \"jet\""), "air.model", "droplet sizes");
    refuse(
        &painting("gun = \"air\"\n[emitter]\ndroplets = \"rosin_rammler\"\nrr_spread = 1.0"),
        "emitter.rr_spread",
        "at least 1.2",
    );
    refuse(&painting("gun = \"air\"\n[emitter]\ngsd = 1.0"), "emitter.gsd", "exceed 1");
    refuse(&painting("gun = \"air\"\n[emitter]\nsauter_mean = -1e-5"), "emitter.sauter_mean", "");
    refuse(&painting("gun = \"air\"\n[air]\nspread = [0.2, 0.0]"), "air.spread", "positive");
    refuse(&painting("gun = \"air\"\n[air]\nviscosity = nan"), "air.viscosity", "");
    refuse(&painting("gun = \"hvlp\"\n[air]\nspeed = 10.0"), "air.speed", "too slow to atomise");
    let exact = scenario(&painting("gun = \"air\""), "air gun").with("simulation.integrator", "exact");
    let (k, m) = refusal(exact, "the exact integrator with air");
    assert_eq!(k, "air.model");
    assert!(m.contains("exact"), "{m}");
    refuse(&painting("gun = \"air\"\ndrag = 0.1"), "air.model", "process.drag");
    // A key the chosen law does not use is refused, not ignored.
    refuse(&painting("gun = \"air\"\n[emitter]\nrr_spread = 2.0"), "emitter.rr_spread", "not a key");
    refuse(&painting("[air]\nspeed = 50.0"), "air.speed", "not a key");
    // The refusal names the file's line.
    let text = painting("gun = \"air\"\nvolume_solids = 2.0");
    match Scenario::from_toml(&text, "paint.toml") {
        Err(ScenarioError::Invalid { location, .. }) => assert_eq!(location, "paint.toml:4"),
        other => panic!("{other:?}"),
    }
}
