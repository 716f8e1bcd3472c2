//! The default layer epoch against epochs of one step (which couple particles and layers step by
//! step): every reported figure of the test scenes (fates, rebound, bounce and trapped ratios,
//! the cushion effect, the thickness mean, CV and radial profile of a static shot, the first
//! failure of a ceiling, the wear of a blasted coat) moves by less than half its own
//! seed-to-seed scatter. The criterion and its derivation are in `spraysim_validate::epochs`;
//! `spraysim validate` runs the same comparison at every epoch length from 1 to 20 ms.

use spraysim::scenario::DEFAULT_LAYER_EPOCH;
use spraysim_validate::epochs::{Plan, compare_all, figures};

const PLAN: Plan = Plan { seeds: 8, shot: 1.0, blast: 0.3 };

#[test]
fn the_default_layer_epoch_moves_no_figure_beyond_half_its_seed_scatter() {
    let reference = figures(&PLAN, 0.001, 0);
    let default = figures(&PLAN, DEFAULT_LAYER_EPOCH, 0);
    let failed: Vec<_> = compare_all(&reference, &default).into_iter().filter(|c| !c.passed).collect();
    assert!(failed.is_empty(), "{failed:#?}");
}

/// The criterion has the power to refuse: an epoch eight times the default (the layer a
/// particle sees lags 1 mm behind at the static shot's centre) shifts the rebound beyond it.
#[test]
fn an_epoch_far_too_long_is_refused() {
    let reference = figures(&PLAN, 0.001, 0);
    let long = figures(&PLAN, 8.0 * DEFAULT_LAYER_EPOCH, 0);
    let refused: Vec<_> =
        compare_all(&reference, &long).into_iter().filter(|c| !c.passed).map(|c| c.name).collect();
    assert!(refused.contains(&"shot: rebound (ACI)"), "refused: {refused:?}");
}
