//! The output directory's contract, tried from outside as a user (or someone who sent the user
//! a results folder) could: links and lists planted in the directory, a second writer, a
//! write blocked part-way, a checkpoint copied in from elsewhere, refused runs.
#![cfg(unix)]

mod common;

use common::{contents, killed_at, listing, one_complete_set, paused_at, signal, spraysim, stderr, wait_for};
use spraysim::scenario::scenes::wall;
use std::os::unix::fs::symlink;
use std::path::Path;

/// 0.1 s onto the wall at 32 × 32 cells, with an impact log every 0.2 s.
fn scene() -> String {
    format!("[simulation]\nduration = 0.1\n[output]\nimpact_log = 0.2\n{}", wall().resolution(32, 32))
}

/// A folder with the scene as `s.toml`, and `victim/keep.txt` beside where the outputs go.
fn setup() -> tempfile::TempDir {
    let tmp = tempfile::tempdir().expect("tempdir");
    std::fs::write(tmp.path().join("s.toml"), scene()).expect("write");
    std::fs::create_dir_all(tmp.path().join("victim")).expect("mkdir");
    std::fs::write(tmp.path().join("victim/keep.txt"), "precious").expect("write");
    tmp
}

fn victim_intact(tmp: &Path) {
    let kept = std::fs::read_to_string(tmp.join("victim/keep.txt")).expect("the file outside is still there");
    assert_eq!(kept, "precious");
}

/// The SHA-256 of `bytes`, as lower-case hex (as the list and `metrics.json` give it).
fn sha256(bytes: &[u8]) -> String {
    use sha2::Digest;
    sha2::Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

/// The list line spraysim writes for a file of these contents.
fn list_line(name: &str, contents: &[u8]) -> String {
    format!("{} {} {name}\n", sha256(contents), contents.len())
}

#[test]
fn stale_file_cleanup_never_deletes_through_a_link_in_the_directory() {
    let tmp = setup();
    let out = tmp.path().join("out");
    std::fs::create_dir(&out).expect("mkdir");
    symlink("../victim", out.join("link")).expect("symlink");
    // The list names the file behind the link, bare and with its true size and hash.
    let list = format!("link/keep.txt\n{}", list_line("link/keep.txt", b"precious"));
    std::fs::write(out.join(".spraysim-files"), list).expect("write");
    let o = spraysim(&["run", "s.toml", "-q", "--set", "simulation.duration=0.02", "-o", "out"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    victim_intact(tmp.path());
    assert!(out.join("link").exists(), "the link itself is the user's: kept");
}

#[test]
fn a_dead_writers_journal_deletes_nothing_outside_and_nothing_the_user_wrote() {
    let tmp = setup();
    let out = tmp.path().join("out");
    std::fs::create_dir(&out).expect("mkdir");
    symlink("../victim", out.join("link")).expect("symlink");
    std::fs::write(out.join("notes.txt"), "my notes").expect("write");
    // A staging folder of a writer long gone, in this version's layout and the one before.
    let dead = out.join(".spraysim-staging-4294967295");
    std::fs::create_dir(&dead).expect("mkdir");
    let journal = format!(
        "index metrics.json\nnew {}new {}old link/keep.txt\nold notes.txt\n",
        list_line("link/keep.txt", b"precious"),
        list_line("notes.txt", b"my notes")
    );
    std::fs::write(dead.join("journal"), journal).expect("write");
    std::fs::write(dead.join(".journal"), "link/keep.txt\nnotes.txt\n").expect("write");
    let o = spraysim(&["run", "s.toml", "-q", "--set", "simulation.duration=0.02", "-o", "out"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    victim_intact(tmp.path());
    assert_eq!(std::fs::read_to_string(out.join("notes.txt")).expect("notes kept"), "my notes");
    assert!(
        !listing(&out).iter().any(|n| n.starts_with(".spraysim-staging-")),
        "the dead writer's folder is gone"
    );
}

#[test]
fn a_file_the_user_put_under_a_listed_name_is_not_removed() {
    let tmp = setup();
    let out = tmp.path().join("out");
    std::fs::create_dir(&out).expect("mkdir");
    // Not an output name at all, though listed with its own hash; an output name whose file the
    // user has since changed; and a true stale output, which goes.
    std::fs::write(out.join("notes.txt"), "my notes").expect("write");
    std::fs::write(out.join("floor_hits.png"), "edited by hand").expect("write");
    std::fs::write(out.join("ghost_hits.png"), "an old map").expect("write");
    let list = [
        list_line("notes.txt", b"my notes"),
        list_line("floor_hits.png", b"as spraysim wrote it"),
        list_line("ghost_hits.png", b"an old map"),
    ]
    .concat();
    std::fs::write(out.join(".spraysim-files"), list).expect("write");
    let o = spraysim(&["run", "s.toml", "-q", "--set", "simulation.duration=0.02", "-o", "out"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let names = listing(&out);
    assert!(names.contains(&"notes.txt".to_string()) && names.contains(&"floor_hits.png".to_string()));
    assert!(!names.contains(&"ghost_hits.png".to_string()), "a stale output spraysim wrote is removed");
}

#[test]
fn links_planted_at_temporary_names_are_never_written_through() {
    let tmp = setup();
    let out = tmp.path().join("out");
    let args = ["run", "s.toml", "-q", "-o", "out", "--checkpoint-every", "20ms"];
    let (mut child, mut err) = paused_at(&args, tmp.path(), "step:10");
    // The names earlier versions used, with the running writer's own process id, this
    // version's, and the checkpoint itself: all links to a file outside.
    let pid = child.id();
    for name in [
        format!(".spraysim-probe-{pid}"),
        format!(".checkpoint.spraysim.{pid}"),
        format!(".spraysim-checkpoint-{pid}-0000000000000000.tmp"),
        "checkpoint.spraysim".to_string(),
    ] {
        symlink("../victim/keep.txt", out.join(name)).expect("symlink");
    }
    // Ctrl-C: the run stops, writes a checkpoint and its outputs so far.
    signal(&child, "INT");
    wait_for(&mut err, "spraysim resume");
    assert_eq!(child.wait().expect("wait").code(), Some(130));
    victim_intact(tmp.path());
    let o = spraysim(&["resume", "out", "-q"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    victim_intact(tmp.path());
    assert!(!listing(&out).iter().any(|n| n.contains("checkpoint")), "{:?}", listing(&out));
}

#[test]
fn a_second_writer_is_refused_naming_the_first_and_the_first_completes_its_set() {
    let tmp = setup();
    let out = tmp.path().join("out");
    let (mut first, mut err) = paused_at(&["run", "s.toml", "-q", "-o", "out"], tmp.path(), "staged");
    let o = spraysim(&["run", "s.toml", "-q", "-o", "out", "--set", "simulation.seed=9"], tmp.path());
    assert!(!o.status.success());
    let message = stderr(&o);
    assert!(
        message.contains("is in use by another spraysim writer")
            && message.contains(&format!("process {}", first.id())),
        "{message}"
    );
    signal(&first, "INT"); // lets the paused run go on: it has already done every step
    wait_for(&mut err, "interrupted"); // what the handler says of the press
    assert!(first.wait().expect("wait").success());
    // The first run's manifest describes the files on disk, the resolved scenario included.
    let metrics = one_complete_set(&out);
    for f in metrics["files"].as_array().expect("manifest") {
        let bytes = std::fs::read(out.join(f["name"].as_str().expect("name"))).expect("read");
        assert_eq!(f["sha256"].as_str(), Some(sha256(&bytes).as_str()), "{}", f["name"]);
    }
    let resolved = std::fs::read_to_string(out.join("scenario.resolved.toml")).expect("read");
    assert!(!resolved.contains("seed = 9"), "the refused run wrote nothing");
}

#[test]
fn a_second_resume_of_one_run_is_refused_while_the_first_goes_on() {
    let tmp = setup();
    let args = ["run", "s.toml", "-q", "-o", "out", "--checkpoint-every", "20ms"];
    killed_at(&args, tmp.path(), "step:50");
    let (mut first, _err) = paused_at(&["resume", "out", "-q"], tmp.path(), "step:60");
    let o = spraysim(&["resume", "out", "-q"], tmp.path());
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains(&format!("in use by another spraysim writer (process {}", first.id())),
        "{}",
        stderr(&o)
    );
    signal(&first, "INT");
    let status = first.wait().expect("wait");
    assert_eq!(status.code(), Some(130), "interrupted, with its outputs so far");
    assert!(tmp.path().join("out/checkpoint.spraysim").exists(), "the first resume's checkpoint stays");
}

#[test]
fn a_folder_in_the_way_of_an_output_is_refused_and_the_previous_set_stays() {
    let tmp = setup();
    let out = tmp.path().join("out");
    assert!(spraysim(&["run", "s.toml", "-q", "-o", "out"], tmp.path()).status.success());
    let before = contents(&out);
    std::fs::remove_file(out.join("wall_thickness.png")).expect("rm");
    std::fs::create_dir(out.join("wall_thickness.png")).expect("mkdir");
    let o = spraysim(&["run", "s.toml", "-q", "-o", "out", "--set", "simulation.seed=2"], tmp.path());
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("wall_thickness.png: is a folder, where an output file goes"),
        "{}",
        stderr(&o)
    );
    std::fs::remove_dir(out.join("wall_thickness.png")).expect("the folder is left as it was");
    let expected: Vec<_> = before.into_iter().filter(|(n, _)| n != "wall_thickness.png").collect();
    assert!(contents(&out) == expected, "the previous set changed");
}

#[test]
fn a_write_that_fails_part_way_moves_the_previous_set_back() {
    let tmp = setup();
    let out = tmp.path().join("out");
    assert!(spraysim(&["run", "s.toml", "-q", "-o", "out"], tmp.path()).status.success());
    let before = contents(&out);
    // The second run also exports the wall as PLY; once its first file has moved in, a folder
    // appears where the PLY goes.
    let args = [
        "run",
        "s.toml",
        "-q",
        "-o",
        "out",
        "--set",
        "simulation.seed=2",
        "--set",
        "output.export=[\"ply\"]",
    ];
    let (mut child, mut err) = paused_at(&args, tmp.path(), "commit:1");
    std::fs::create_dir(out.join("wall.ply")).expect("mkdir");
    signal(&child, "INT");
    wait_for(&mut err, "writing outputs to out");
    assert!(!child.wait().expect("wait").success());
    std::fs::remove_dir(out.join("wall.ply")).expect("the folder is left as it was");
    assert!(contents(&out) == before, "the directory does not hold the previous set");
    assert!(!listing(&out).iter().any(|n| n.starts_with(".spraysim-staging-")));
    one_complete_set(&out);
}

#[test]
fn a_checkpoint_copied_from_another_runs_directory_is_refused() {
    let tmp = setup();
    let args = ["run", "s.toml", "-q", "-o", "a", "--checkpoint-every", "20ms"];
    killed_at(&args, tmp.path(), "step:50");
    let o = spraysim(&["run", "s.toml", "-q", "-o", "b", "--set", "simulation.seed=5"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let b = tmp.path().join("b");
    let before = contents(&b);
    std::fs::copy(tmp.path().join("a/checkpoint.spraysim"), b.join("checkpoint.spraysim")).expect("cp");
    let o = spraysim(&["resume", "b", "-q"], tmp.path());
    assert!(!o.status.success());
    assert!(stderr(&o).contains("checkpoint.spraysim: belongs to another run"), "{}", stderr(&o));
    let after: Vec<_> = contents(&b).into_iter().filter(|(n, _)| n != "checkpoint.spraysim").collect();
    assert!(after == before, "the directory's outputs changed");
    // In its own directory it resumes.
    let o = spraysim(&["resume", "a", "-q"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn a_checkpoint_with_a_nan_position_is_refused_not_looped_on() {
    use spraysim::output::checkpoint::{Checkpoint, read_checkpoint, write_checkpoint};
    let tmp = setup();
    let args = ["run", "s.toml", "-q", "-o", "out", "--checkpoint-every", "20ms"];
    killed_at(&args, tmp.path(), "step:50");
    let out = tmp.path().join("out");
    let mut ck: Checkpoint = read_checkpoint(&out).expect("a checkpoint");
    // The state begins with its version (4 bytes), the step (8), the step the last epoch ended
    // (8), the nozzle's particle volume (8), the released particles (a count of 8, none here)
    // and the particles' count (8): the first particle's anchor x follows.
    assert_eq!(u64::from_le_bytes(ck.state[28..36].try_into().expect("8 bytes")), 0, "no released material");
    ck.state[44..52].copy_from_slice(&f64::NAN.to_le_bytes());
    let dir = spraysim::output::OutputDir::lock(&out).expect("lock");
    write_checkpoint(&dir, &ck).expect("written with a checksum made anew");
    drop(dir);
    let o = spraysim(&["resume", "out", "-q"], tmp.path());
    assert!(!o.status.success());
    let message = stderr(&o);
    assert!(
        message.contains("the saved state is invalid: particle") && message.contains("non-finite position"),
        "{message}"
    );
}

#[test]
fn a_thread_count_beyond_the_machine_is_refused_at_once_and_writes_nothing() {
    let tmp = setup();
    let o = spraysim(&["run", "s.toml", "-q", "-o", "out", "-j", "100000"], tmp.path());
    assert!(!o.status.success());
    assert!(stderr(&o).contains("cannot start 100000 worker threads: at most"), "{}", stderr(&o));
    assert!(!tmp.path().join("out").exists());
}

#[test]
fn a_refused_run_leaves_no_folder_behind() {
    let tmp = setup();
    for bad in [["--set", "emitter.speed=[-1, 2]"], ["-j", "100000"]] {
        let mut args = vec!["run", "s.toml", "-q", "-o", "a/b/c"];
        args.extend(bad);
        let o = spraysim(&args, tmp.path());
        assert!(!o.status.success());
        assert!(!tmp.path().join("a").exists(), "{bad:?} left a folder");
    }
}

#[test]
fn an_output_directory_that_is_a_file_is_named_as_such() {
    let tmp = setup();
    std::fs::write(tmp.path().join("out"), "a file").expect("write");
    let o = spraysim(&["run", "s.toml", "-q", "-o", "out"], tmp.path());
    assert!(!o.status.success());
    assert!(stderr(&o).contains("output directory out: out: is a file, not a folder"), "{}", stderr(&o));
}

#[test]
fn an_output_directory_that_is_not_utf8_is_refused_not_renamed() {
    use std::os::unix::ffi::OsStrExt;
    let tmp = setup();
    let name = std::ffi::OsStr::from_bytes(b"out\xff");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_spraysim"))
        .args(["run", "s.toml", "-q", "-o"])
        .arg(name)
        .current_dir(tmp.path())
        .output()
        .expect("starts");
    assert!(!o.status.success());
    assert!(stderr(&o).contains("not valid UTF-8"), "{}", stderr(&o));
    assert_eq!(listing(tmp.path()), ["s.toml", "victim"], "nothing was written under another name");
}
