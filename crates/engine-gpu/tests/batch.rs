//! Batches: simulations whose calls fly together in shared dispatches give, each, the bits of
//! its run alone, whatever the others are (other scenes, processes and lengths; some eroding,
//! whose calls span one epoch, beside others of many), and a member whose run ends first does
//! not hold the others up.

mod common;

use spraysim_engine::Simulation;
use spraysim_engine::deposit::DepositSurface;
use spraysim_gpu::run_together;
use spraysim_scenario::Scenario;
use spraysim_scenario::scenes::{NOZZLE_AT_WALL, failing_layer, floor, scenario, wall};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

/// What a run leaves, to the bit: its layers, metrics and particles in flight.
fn outcome(sim: &Simulation) -> (Vec<Vec<u64>>, String, String) {
    let layers =
        sim.targets().iter().map(|t| t.surface.thickness().iter().map(|x| x.to_bits()).collect()).collect();
    (layers, format!("{:?}", sim.metrics()), format!("{:?}", sim.swarm().particles))
}

/// Shotcrete onto the wall for `duration` s with `seed`.
fn shotcrete(duration: f64, seed: u64) -> Scenario {
    let text = format!(
        "[simulation]\nduration = {duration:?}\nseed = {seed}\n[emitter]\nspawn_rate = 20000.0\n{NOZZLE_AT_WALL}{}{}",
        wall().resolution(128, 128),
        floor().resolution(60, 45),
    );
    scenario(&text, "shotcrete")
}

#[test]
fn runs_in_a_batch_give_the_bits_of_their_runs_alone() {
    // Its own stage: its profile counts this test's dispatches alone.
    let Some(gpu) = common::own_gpu().map(std::sync::Arc::new) else { return };
    let blasting = {
        let text = format!(
            "[simulation]\nduration = 0.2\nseed = 5\n[process]\npreset = \"blasting\"\n[emitter]\nspawn_rate = 20000.0\n{NOZZLE_AT_WALL}{}",
            wall().size(0.6, 0.6).resolution(60, 60).coating(5e-6),
        );
        scenario(&text, "blasting")
    };
    let arch = scenario(
        "[simulation]\nduration = 0.2\nseed = 6\n[emitter]\nspawn_rate = 20000.0\n\
         [nozzle]\nposition = [0.0, 0.0, 0.2]\naxis = [0.0, 0.0, 1.0]\n\
         [[target]]\nname = \"arch\"\nshape = \"cylinder\"\ncenter = [0.0, 0.0, 0.0]\naxis = [0.0, 1.0, 0.0]\n\
         radius = 1.5\nlength = 2.0\nangles = [45.0, 135.0]\nresolution = [118, 100]\n",
        "arch",
    );
    // Shotcrete of two lengths (the short one leaves first), grit on a coat (its calls span one
    // epoch each, so it flies in dispatches of its own), a lining, and a weak layer whose
    // failures release material that flies again.
    let scenarios = [shotcrete(0.3, 3), shotcrete(0.1, 4), blasting, arch, failing_layer(0.4, 7)];
    gpu.take_profile();
    let (alone, calls): (Vec<_>, Vec<u64>) =
        scenarios.iter().map(|s| (outcome(&common::run(s, Some(&gpu))), gpu.take_profile().calls)).unzip();
    let sims: Vec<Simulation> = scenarios.iter().map(|s| s.build().expect("builds")).collect();
    let stop = AtomicBool::new(false);
    let together = run_together(&gpu, sims, &stop, |_, sim| {
        assert_eq!(sim.flight_stage_error(), None, "a member's call fell back to the CPU");
        outcome(&sim)
    })
    .expect("a batch");
    // The two shotcrete runs and the lining end their calls at the same steps (their layer
    // stages' intervals): theirs share dispatches, as the short run's share the long one's.
    let dispatches = gpu.take_profile().calls;
    let shared = calls[1] + calls[3];
    assert!(
        shared > 0 && dispatches <= calls.iter().sum::<u64>() - shared,
        "{dispatches} dispatches for {calls:?}"
    );
    for (k, (a, b)) in alone.iter().zip(&together).enumerate() {
        assert!(a.0 == b.0, "scenario {k}: the layers differ");
        assert_eq!(a.1, b.1, "scenario {k}: the metrics differ");
        assert!(a.2 == b.2, "scenario {k}: the particles in flight differ");
    }
    assert!(together[4].1.contains("released"), "the weak layer's metrics");
}

#[test]
fn a_batch_stops_when_asked_and_each_member_s_run_can_go_on_alone() {
    let Some(gpu) = common::gpu() else { return };
    let sims: Vec<Simulation> = (0..3).map(|k| shotcrete(0.3, 10 + k).build().expect("builds")).collect();
    let stop = AtomicBool::new(true);
    let stopped = run_together(&gpu, sims, &stop, |_, sim| sim).expect("a batch");
    assert!(stopped.iter().all(|s| s.steps_done() == 0), "stopped before their first call");
    for mut sim in stopped {
        sim.set_flight_stage(Some(gpu.clone()));
        sim.run(|_| {});
        assert!(sim.is_finished() && sim.flight_stage_error().is_none());
    }
}

#[test]
fn a_run_that_changes_stages_midway_gives_the_bits_of_a_run_on_one() {
    // Two stages of their own on one adapter: the second's calls change the layers the first's
    // copy holds, which it must then copy whole, not bring up to date from what changed after.
    let (Some(first), Some(second)) = (common::own_gpu(), common::own_gpu()) else { return };
    let (first, second) = (std::sync::Arc::new(first), std::sync::Arc::new(second));
    let scenario = failing_layer(0.4, 8);
    let on_one = common::run(&scenario, Some(&first));
    let mut switched = scenario.build().expect("builds");
    let mut calls = 0;
    while !switched.is_finished() {
        let stage: std::sync::Arc<dyn spraysim_engine::pipeline::FlightStage> =
            if calls % 3 == 1 { second.clone() } else { first.clone() };
        switched.set_flight_stage(Some(stage));
        switched.advance_call(switched.steps_to_call_end());
        calls += 1;
    }
    assert!(calls >= 4, "{calls} calls");
    assert!(outcome(&switched) == outcome(&on_one), "the run that changed stages differs");
}

#[test]
fn stepping_together_gives_the_bits_of_stepping_each_alone() {
    let Some(gpu) = common::own_gpu().map(std::sync::Arc::new) else { return };
    // Two runs on the GPU and one on the CPU, stepped 37 steps at a time (calls end within
    // epochs), as a vectorised environment steps its environments.
    let scenarios = [shotcrete(0.2, 21), failing_layer(0.3, 22), shotcrete(0.15, 23)];
    let build = |k: usize| {
        let mut sim = scenarios[k].build().expect("builds");
        if k < 2 {
            sim.set_flight_stage(Some(gpu.clone()));
        }
        sim
    };
    let alone: Vec<_> = (0..3)
        .map(|k| {
            let mut sim = build(k);
            while !sim.is_finished() {
                sim.advance(37.min(sim.total_steps() - sim.steps_done()));
            }
            outcome(&sim)
        })
        .collect();
    let mut sims: Vec<Simulation> = (0..3).map(build).collect();
    let stop = AtomicBool::new(false);
    let stage = |s: &Simulation| s.flight_stage().map(|g| Arc::as_ptr(g).cast::<()>());
    let mut rounds = 0;
    let mut first: Vec<Option<*const ()>> = Vec::new();
    while sims.iter().any(|s| !s.is_finished()) {
        let mut refs: Vec<&mut Simulation> = sims.iter_mut().collect();
        spraysim_gpu::step_together(&gpu, &mut refs, 37, &stop).expect("steps");
        rounds += 1;
        if rounds == 3 {
            // Between two vectorised steps, one of them stepped on its own, in its batch alone.
            sims[0].advance(5);
            assert_eq!(sims[0].flight_stage_error(), None, "a member flies on its own");
        }
        if first.is_empty() {
            first = sims.iter().map(stage).collect();
        } else {
            let now: Vec<_> = sims.iter().map(stage).collect();
            assert_eq!(now, first, "each stays in its batch from one vectorised step to the next");
        }
    }
    assert!(rounds > 5);
    for (k, (sim, a)) in sims.iter().zip(&alone).enumerate() {
        assert_eq!(sim.flight_stage().is_some(), k < 2, "those on the GPU stay there");
        assert!(sim.is_finished() && sim.flight_stage_error().is_none(), "scenario {k}");
        // The first was stepped on its own once in between, which moved where its calls end.
        if k != 0 {
            assert!(outcome(sim) == *a, "scenario {k} stepped together differs from its steps alone");
        }
    }
}

#[test]
fn a_simulation_that_replaces_one_stepped_together_takes_its_region_and_the_others_stay() {
    // Its own stage: its profile counts this test's dispatches alone.
    let Some(gpu) = common::own_gpu().map(Arc::new) else { return };
    let steps = 37;
    let on_gpu = |sc: &Scenario| {
        let mut sim = sc.build().expect("builds");
        sim.set_flight_stage(Some(gpu.clone()));
        sim
    };
    let alone = |sc: &Scenario| {
        let mut sim = on_gpu(sc);
        while !sim.is_finished() {
            sim.advance(steps.min(sim.total_steps() - sim.steps_done()));
        }
        outcome(&sim)
    };
    // Three environments; after two vectorised steps the second is reset into a new run of the
    // same grids (another seed and length), as an environment whose episode ended.
    let scenarios = [shotcrete(0.2, 41), shotcrete(0.2, 42), shotcrete(0.2, 43)];
    let replacement = shotcrete(0.15, 44);
    let expected = [alone(&scenarios[0]), alone(&replacement), alone(&scenarios[2])];
    let mut sims: Vec<Simulation> = scenarios.iter().map(on_gpu).collect();
    let stop = AtomicBool::new(false);
    let stage = |s: &Simulation| s.flight_stage().map(|g| Arc::as_ptr(g).cast::<()>());
    let step = |sims: &mut [Simulation]| {
        let mut refs: Vec<&mut Simulation> = sims.iter_mut().collect();
        spraysim_gpu::step_together(&gpu, &mut refs, steps, &stop).expect("steps");
    };
    step(&mut sims);
    step(&mut sims);
    let before: Vec<_> = sims.iter().map(stage).collect();
    // Its region's copy of the layers holds the run it replaces: the first call must rebuild it.
    sims[1] = on_gpu(&replacement);
    gpu.take_profile();
    step(&mut sims);
    let p = gpu.take_profile();
    let after: Vec<_> = sims.iter().map(stage).collect();
    assert!(after[0] == before[0] && after[2] == before[2], "the others stay in their batch");
    assert!(after[1].is_some() && after[1] != before[1], "the new run flies as a member of its own");
    assert_eq!(p.whole, 1, "only the new run's region is rebuilt ({} members flown)", p.members);
    assert!(sims[1].flight_stage().is_some_and(|s| s.describe().ends_with("in a batch of 3")));
    while sims.iter().any(|s| !s.is_finished()) {
        step(&mut sims);
    }
    for (k, (sim, e)) in sims.iter().zip(&expected).enumerate() {
        assert_eq!(sim.flight_stage_error(), None, "environment {k}");
        assert!(outcome(sim) == *e, "environment {k} stepped together differs from its steps alone");
    }
}

#[test]
fn copies_of_a_simulation_stepped_together_fly_as_members_of_their_own() {
    let Some(gpu) = common::own_gpu().map(Arc::new) else { return };
    let stop = AtomicBool::new(false);
    let mut original = shotcrete(0.1, 31).build().expect("builds");
    original.set_flight_stage(Some(gpu.clone()));
    spraysim_gpu::step_together(&gpu, &mut [&mut original], 20, &stop).expect("steps");
    // The copy shares the original's stage, a member of the original's batch.
    let mut copy = original.clone();
    let stage = |s: &Simulation| s.flight_stage().map(|g| Arc::as_ptr(g).cast::<()>());
    assert_eq!(stage(&copy), stage(&original));
    while !original.is_finished() {
        spraysim_gpu::step_together(&gpu, &mut [&mut original, &mut copy], 20, &stop).expect("steps");
        assert_ne!(stage(&copy), stage(&original), "each copy in a member of its own");
    }
    assert!(copy.is_finished() && copy.flight_stage_error().is_none());
    assert!(outcome(&copy) == outcome(&original), "a copy stepped beside its original gives its bits");
}
