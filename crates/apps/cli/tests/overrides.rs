//! `--set` overrides as the user sees them: applied together in any order, a motion of another
//! kind set by replacing the nozzle's table, and every refusal naming the override.

mod common;

use common::{spraysim, stderr};
use spraysim::scenario::DEFAULT_SCENE;

/// The default scene's nozzle is static: a raster set into its table is refused, naming the
/// override (not a line of the built-in scene, which the user never wrote) and the table form.
#[test]
fn a_raster_set_into_the_default_static_nozzle_names_the_override_and_the_table_form() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let o = spraysim(&["run", "--set", "nozzle.raster={target=\"wall\"}", "-o", "res"], tmp.path());
    assert!(!o.status.success());
    assert_eq!(
        stderr(&o),
        "error: --set nozzle.raster={target=\"wall\"}: `nozzle.raster` belongs to a raster nozzle, but [nozzle] \
         also has `nozzle.position` and `nozzle.axis`, keys of a static or circling nozzle: a nozzle moves one way \
         only; to change how it moves, set the whole table, which replaces the scenario's: \
         nozzle={raster = {target = \"wall\"}}\n"
    );
    assert!(!tmp.path().join("res").exists(), "a refused run writes nothing");
}

/// The table form the refusal suggests replaces the nozzle wholesale.
#[test]
fn the_nozzle_table_set_whole_becomes_a_raster() {
    let tmp = tempfile::tempdir().expect("tempdir");
    std::fs::write(tmp.path().join("s.toml"), DEFAULT_SCENE).expect("write");
    let o = spraysim(
        &["check", "s.toml", "--resolved", "--set", "nozzle={raster={target=\"wall\"}}"],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let resolved = String::from_utf8_lossy(&o.stdout);
    assert!(resolved.contains("[nozzle.raster]\ntarget = \"wall\""), "{resolved}");
    assert!(!resolved.contains("position = [-1.0, 0.0, 1.0]"), "the static pose is gone: {resolved}");
}

/// A circle's radius and frequency, each refused alone, are accepted in either order: the
/// overrides are checked together.
#[test]
fn overrides_are_checked_together_in_either_order() {
    let tmp = tempfile::tempdir().expect("tempdir");
    std::fs::write(tmp.path().join("s.toml"), DEFAULT_SCENE).expect("write");
    let check = |first: &str, second: &str| {
        let o = spraysim(&["check", "s.toml", "--resolved", "--set", first, "--set", second], tmp.path());
        assert!(o.status.success(), "--set {first} --set {second}: {}", stderr(&o));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let (radius, frequency) = ("nozzle.circle_radius=0.05", "nozzle.circle_frequency=2");
    let one = check(radius, frequency);
    assert_eq!(one, check(frequency, radius));
    assert!(one.contains("circle_radius = 0.05"), "{one}");
}

/// A refused override names itself, with the message the key's check gives.
#[test]
fn a_refused_override_names_itself() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let o = spraysim(&["run", "--set", "nozzle.circle_radius=0.05", "-o", "res"], tmp.path());
    assert!(!o.status.success());
    assert_eq!(
        stderr(&o),
        "error: --set nozzle.circle_radius=0.05: `nozzle.circle_radius` needs circle_frequency > 0 and a static \
         nozzle\n"
    );
}
