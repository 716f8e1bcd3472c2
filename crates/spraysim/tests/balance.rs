//! Every emitted particle is accounted for from the maps: Σ thickness × cell area over every
//! target, plus the backs of targets, obstacles, left domain, expired and in flight, equals the
//! emitted volume, in the README's default run and in every example.

use spraysim::Scenario;

fn assert_balanced(name: &str, sc: &Scenario) {
    let mut sim = sc.build().expect("valid");
    sim.run(|_| {});
    let b = sim.metrics().volume_balance;
    assert!(b.residual.abs() <= 1e-6 * b.emitted, "{name}: {b:?}");
    assert!(b.in_maps > 0.0, "{name}: {b:?}");
}

#[test]
fn the_volume_balance_closes_from_the_maps_in_the_default_run_and_every_example() {
    assert_balanced("default scene", &Scenario::default_scene());
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples");
    let mut seen = 0;
    let mut entries: Vec<_> =
        std::fs::read_dir(dir).expect("examples").map(|e| e.expect("entry").path()).collect();
    entries.sort();
    for path in entries.iter().filter(|p| p.extension().is_some_and(|e| e == "toml")) {
        // The first 3 s of each: the raster's lowest passes, rebound, slump and all.
        let sc = Scenario::from_path(path)
            .and_then(|sc| {
                let d = sc.simulation().duration.min(3.0);
                sc.with("simulation.duration", d)
            })
            .unwrap_or_else(|e| panic!("{e}"));
        let name = path.display().to_string();
        if name.contains("blasting") {
            // Grit leaves no deposit: its balance is all in the fates.
            let mut sim = sc.build().expect("valid");
            sim.run(|_| {});
            let b = sim.metrics().volume_balance;
            assert!(b.residual.abs() <= 1e-6 * b.emitted && b.in_maps == 0.0, "{name}: {b:?}");
        } else {
            assert_balanced(&name, &sc);
        }
        seen += 1;
    }
    assert!(seen >= 5, "{seen} examples");
}
