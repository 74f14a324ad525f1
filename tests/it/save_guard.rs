//! `run --save` looks at what an existing file is, not at its name: it writes over a recording
//! of its own (a regular file with one name that starts with Rerun's header), never over the
//! scene being run under any name, and over anything else only with `--force`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common::temp_path;

/// A fresh folder for one test's files.
fn folder(name: &str) -> PathBuf {
    let dir = temp_path(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A copy of the passive-bending scene in `dir`.
fn scene_in(dir: &Path) -> PathBuf {
    let scene = dir.join("scene.toml");
    let shipped = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/passive_bending.toml");
    std::fs::copy(shipped, &scene).unwrap();
    scene
}

/// `rodlab run SCENE --frames 2 --save OUT` (and `--force`).
fn save(scene: &Path, out: &Path, force: bool) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_rodlab"));
    command
        .arg("run")
        .arg(scene)
        .args(["--frames", "2", "--save"])
        .arg(out);
    if force {
        command.arg("--force");
    }
    command.output().unwrap()
}

/// Asserts that the run was refused with a message about `--save` containing `why`.
fn assert_refused(output: &Output, why: &str) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "not refused: {stderr}");
    assert!(
        stderr.contains("--save") && stderr.contains(why),
        "{why:?} not in {stderr}"
    );
}

/// A hard link to the scene is the scene: refused, even with `--force`.
#[test]
fn save_refuses_a_hard_link_to_the_scene() {
    let dir = folder("guard_scene_link");
    let scene = scene_in(&dir);
    let original = std::fs::read(&scene).unwrap();
    let link = dir.join("scene_link.rrd");
    std::fs::hard_link(&scene, &link).unwrap();
    for force in [false, true] {
        assert_refused(&save(&scene, &link, force), "the scene being run");
    }
    assert_eq!(std::fs::read(&scene).unwrap(), original);
}

/// A symbolic link named `*.rrd` to a text file, and a text file named `fake.rrd`: refused
/// without `--force`, untouched; written over with it.
#[test]
fn save_refuses_a_symlink_or_a_text_file_named_rrd_without_force() {
    let dir = folder("guard_named_rrd");
    let scene = scene_in(&dir);
    let notes = dir.join("notes.txt");
    std::fs::write(&notes, "keep me").unwrap();
    let link = dir.join("link.rrd");
    std::os::unix::fs::symlink(&notes, &link).unwrap();
    let fake = dir.join("fake.rrd");
    std::fs::write(&fake, "not a recording").unwrap();
    assert_refused(&save(&scene, &link, false), "symbolic link");
    assert_refused(&save(&scene, &fake, false), "not an .rrd recording");
    assert_eq!(std::fs::read_to_string(&notes).unwrap(), "keep me");
    assert_eq!(std::fs::read_to_string(&fake).unwrap(), "not a recording");
    assert!(save(&scene, &fake, true).status.success());
    assert!(std::fs::read(&fake).unwrap().starts_with(b"RRF"));
}

/// A recording with a second name (a hard link): writing would change both; refused without
/// `--force`.
#[test]
fn save_refuses_a_recording_with_another_hard_link_without_force() {
    let dir = folder("guard_recording_link");
    let scene = scene_in(&dir);
    let first = dir.join("first.rrd");
    assert!(save(&scene, &first, false).status.success());
    let before = std::fs::read(&first).unwrap();
    let second = dir.join("second.rrd");
    std::fs::hard_link(&first, &second).unwrap();
    assert_refused(&save(&scene, &second, false), "hard links");
    assert_eq!(std::fs::read(&first).unwrap(), before);
}

/// A recording of its own (and an empty file, which holds nothing to lose) is written over
/// without `--force`.
#[test]
fn save_writes_over_a_recording_or_an_empty_file() {
    let dir = folder("guard_overwrite");
    let scene = scene_in(&dir);
    let out = dir.join("run.rrd");
    assert!(save(&scene, &out, false).status.success());
    let again = save(&scene, &out, false);
    assert!(again.status.success(), "{:?}", again);
    let empty = dir.join("empty.rrd");
    std::fs::write(&empty, "").unwrap();
    assert!(save(&scene, &empty, false).status.success());
    assert!(std::fs::read(&empty).unwrap().starts_with(b"RRF"));
}
