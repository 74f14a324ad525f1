//! Recordings: a written file decodes with Rerun's own decoder and holds body poses for every
//! frame; a run that explodes stops with an error naming the body, the constraint and the frame,
//! and its recording up to that frame stays readable.

use std::collections::BTreeSet;

use crate::common::{decode, decode_prefix, frames_with, static_texts, temp_path};
use rodlab::cli::record_scene;
use rodlab::record;
use rodlab::scene::Scene;
use rodlab::sim::Overrides;

/// The passive-bending scene, cut to `frames` frames.
fn passive_bending(frames: u32) -> Scene {
    let mut scene = Scene::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/passive_bending.toml"
    ))
    .unwrap();
    Overrides {
        frames: Some(frames),
        ..Default::default()
    }
    .apply(&mut scene.def);
    scene
}

#[test]
fn recording_holds_body_poses_for_every_frame() {
    let path = temp_path("passive_bending.rrd");
    let scene = passive_bending(40);
    let report = record_scene(&scene, record::save_to(&path, &scene).unwrap()).unwrap();
    assert_eq!(report.frames, 40);
    let chunks = decode(&path);
    let expected: BTreeSet<i64> = (0..=40).collect();
    for (entity, component) in [
        ("world/ragdolls/capsules", "translations"),
        ("world/ragdolls/capsules", "quaternions"),
        ("metrics/dislocation_cm", "scalars"),
        // the rod spine's centerline, material frames, scalars and bones
        ("world/ragdolls/rods/centerlines", "strips"),
        ("world/ragdolls/rods/frames", "vectors"),
        ("metrics/rod", "scalars"),
        ("world/ragdolls/bones/arc", "strips"),
    ] {
        assert_eq!(
            frames_with(&chunks, entity, component),
            expected,
            "{entity} {component}"
        );
    }
    // shapes are static
    assert!(chunks
        .iter()
        .any(|c| c.is_static() && c.entity_path().to_string() == "/world/ragdolls/capsules"));
    // residuals: one series per ragdoll in one entity, named after it, both every frame
    let names = static_texts(&chunks, "metrics/dislocation_cm", "names");
    assert_eq!(names, ["chain3", "rod"]);
    let widths: BTreeSet<usize> = (chunks.iter())
        .filter(|c| !c.is_static() && c.entity_path().to_string() == "/metrics/dislocation_cm")
        .flat_map(|c| {
            let d = (c.component_descriptors())
                .find(|d| d.component.as_str().ends_with("scalars"))
                .unwrap();
            c.iter_slices::<f64>(d.component)
                .map(|values| values.iter().filter(|v| v.is_finite()).count())
                .collect::<Vec<_>>()
        })
        .collect();
    assert_eq!(widths, BTreeSet::from([2]), "finite values per frame");
}

/// `rodlab run --record-from T` records only the frames from simulated time T on (the run
/// itself still starts at 0), with the shapes still there; the report covers the whole run.
#[test]
fn recording_from_a_time_keeps_only_the_later_frames() {
    let path = temp_path("passive_bending_late.rrd");
    let scene = passive_bending(40);
    // frame 30 is at 0.5 s
    let report =
        rodlab::cli::record_scene_from(&scene, record::save_to(&path, &scene).unwrap(), 0.5)
            .unwrap();
    assert_eq!(
        report.total_dislocation_cm.len(),
        40,
        "the report covers every frame"
    );
    let chunks = decode(&path);
    let expected: BTreeSet<i64> = (30..=40).collect();
    for (entity, component) in [
        ("world/ragdolls/capsules", "translations"),
        ("metrics/dislocation_cm", "scalars"),
    ] {
        assert_eq!(
            frames_with(&chunks, entity, component),
            expected,
            "{entity} {component}"
        );
    }
    assert!(chunks
        .iter()
        .any(|c| c.is_static() && c.entity_path().to_string() == "/world/ragdolls/capsules"));
}

const EXPLODING: &str = r#"
dt = 0.016666668
iterations = 10
frames = 100

[[body]]
name = "anchor"
kind = "fixed"
shape = "sphere"
radius = 0.05

[[body]]
name = "bob"
shape = "sphere"
radius = 0.05
mass = 1.0
position = [0.0, -1.0, 0.0]
velocity = [0.0, 0.0, 40.0]

[[joint]]
name = "rope"
a = "anchor"
b = "bob"
anchor = [0.0, 0.0, 0.0]
"#;

#[test]
fn explosion_names_body_constraint_and_frame_and_keeps_the_recording() {
    // A 1 m pendulum whirled at 40 m/s, then the bound lowered below what it reaches: the run
    // must stop at the first frame above the bound.
    let path = temp_path("explode.rrd");
    let mut scene = Scene::parse("explode.toml", EXPLODING).unwrap();
    scene.def.max_speed = 30.0;
    let err = record_scene(&scene, record::save_to(&path, &scene).unwrap()).expect_err("must stop");
    let text = format!("{err:#}");
    assert!(
        text.contains("body \"bob\"") && text.contains("\"rope\"") && text.contains("frame 1:"),
        "{text}"
    );
    let chunks = decode(&path);
    assert_eq!(
        frames_with(&chunks, "world/loose/spheres", "centers"),
        BTreeSet::from([0])
    );
    assert!(chunks
        .iter()
        .any(|c| c.entity_path().to_string() == "/failure"));
}

#[test]
fn nan_stops_the_run() {
    let mut scene = Scene::parse("nan.toml", EXPLODING).unwrap();
    let mut lab = scene.build().unwrap();
    let bob = lab.world.find_body("bob").unwrap();
    lab.world.body_mut(bob).linear_velocity.x = f32::NAN;
    scene.def.frames = 5;
    let err = rodlab::sim::run(&mut lab, 5, &mut rodlab::sim::NoObserver)
        .expect_err("NaN must stop the run");
    let text = err.to_string();
    assert!(
        text.contains("bob") && text.contains("NaN") && text.contains("rope"),
        "{text}"
    );
}

/// Three runs of the drop give one state hash (bit for bit the same final state), a change of
/// method gives another, and the recording stores the hash the summary prints.
#[test]
fn three_runs_give_one_state_hash_and_the_recording_keeps_it() {
    let mut scene = Scene::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/ragdoll_drop.toml"
    ))
    .unwrap();
    Overrides {
        frames: Some(45),
        ..Default::default()
    }
    .apply(&mut scene.def);
    let hashes: Vec<u64> = (0..3)
        .map(|_| {
            let mut lab = scene.build().unwrap();
            rodlab::sim::run(&mut lab, 45, &mut rodlab::sim::NoObserver)
                .unwrap()
                .state_hash
        })
        .collect();
    assert!(hashes.iter().all(|&h| h == hashes[0]), "{hashes:x?}");
    let mut other = scene.clone();
    other.def.iterations += 1;
    let mut lab = other.build().unwrap();
    let changed = rodlab::sim::run(&mut lab, 45, &mut rodlab::sim::NoObserver).unwrap();
    assert_ne!(changed.state_hash, hashes[0]);
    let path = temp_path("drop_hash.rrd");
    let report = record_scene(&scene, record::save_to(&path, &scene).unwrap()).unwrap();
    assert_eq!(report.state_hash, hashes[0]);
    let stored = static_texts(&decode(&path), "state_hash", "text");
    assert_eq!(stored, vec![format!("{:016x}", hashes[0])]);
}

/// `run --save` refuses to write over the scene being run, and over an existing file that is
/// not an `.rrd` unless `--force`; the files stay as they were.
#[test]
fn save_refuses_to_overwrite_the_scene_or_a_file_that_is_not_a_recording() {
    let scene = temp_path("guarded.toml");
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/passive_bending.toml"),
        &scene,
    )
    .unwrap();
    let notes = temp_path("notes.txt");
    std::fs::write(&notes, "keep me").unwrap();
    let run = |save: &std::path::Path, force: bool| {
        let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_rodlab"));
        command
            .arg("run")
            .arg(&scene)
            .args(["--frames", "2", "--save"])
            .arg(save);
        if force {
            command.arg("--force");
        }
        command.output().unwrap()
    };
    let original = std::fs::read_to_string(&scene).unwrap();
    for (target, force) in [(&scene, false), (&scene, true), (&notes, false)] {
        let out = run(target, force);
        assert!(!out.status.success(), "{target:?} force {force}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains("--save"), "{stderr}");
    }
    assert_eq!(std::fs::read_to_string(&scene).unwrap(), original);
    assert_eq!(std::fs::read_to_string(&notes).unwrap(), "keep me");
    assert!(run(&notes, true).status.success());
}

/// SIGTERM (and SIGINT, the same path) stops a run at the next frame: the summary is printed,
/// the recording is finished (it decodes, with every frame up to the stop and the final state
/// hash), and the exit code is 143.
#[test]
fn sigterm_stops_at_a_frame_prints_the_summary_and_finishes_the_recording() {
    let path = temp_path("terminated.rrd");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_rodlab"))
        .args([
            "run",
            concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/ragdoll_drop.toml"),
        ])
        .args([
            "--spine",
            "rod",
            "--frames",
            "600000",
            "--record-every",
            "1",
            "--save",
        ])
        .arg(&path)
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // let it record for a while
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let killed = std::process::Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    let mut stdout = String::new();
    std::io::Read::read_to_string(child.stdout.as_mut().unwrap(), &mut stdout).unwrap();
    assert_eq!(status.code(), Some(143), "{stdout}");
    let stopped = stdout
        .lines()
        .find_map(|l| l.trim().strip_prefix("stopped by SIGTERM after "))
        .unwrap_or_else(|| panic!("no stop line in {stdout}"));
    let frames: i64 = stopped.split(' ').next().unwrap().parse().unwrap();
    assert!(frames > 0 && frames < 600000, "{stopped}");
    let chunks = decode(&path);
    let recorded = frames_with(&chunks, "world/ragdolls/capsules", "translations");
    assert_eq!(recorded, (0..=frames).collect::<BTreeSet<i64>>());
    assert!(chunks
        .iter()
        .any(|c| c.is_static() && c.entity_path().to_string() == "/state_hash"));
}

/// `[record] every = N` (`--record-every N`) records frames 0, N, 2N, ... only: poses and
/// scalars alike, in a smaller file; the run itself still steps every frame.
#[test]
fn record_every_keeps_every_nth_frame() {
    let load = |every: u32| {
        let mut scene = Scene::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/scenes/passive_bending.toml"
        ))
        .unwrap();
        Overrides {
            frames: Some(40),
            record_every: Some(every),
            ..Default::default()
        }
        .apply(&mut scene.def);
        scene
    };
    let (all, sparse) = (temp_path("every1.rrd"), temp_path("every3.rrd"));
    for (path, every) in [(&all, 1), (&sparse, 3)] {
        let scene = load(every);
        let report = record_scene(&scene, record::save_to(path, &scene).unwrap()).unwrap();
        assert_eq!(report.frames, 40);
    }
    let chunks = decode(&sparse);
    let expected: BTreeSet<i64> = (0..=40).filter(|f| f % 3 == 0).collect();
    for (entity, component) in [
        ("world/ragdolls/capsules", "translations"),
        ("metrics/dislocation_cm", "scalars"),
        ("metrics/rod", "scalars"),
    ] {
        assert_eq!(
            frames_with(&chunks, entity, component),
            expected,
            "{entity}"
        );
    }
    let size = |p: &std::path::Path| std::fs::metadata(p).unwrap().len();
    assert!(
        size(&sparse) < size(&all),
        "{} vs {}",
        size(&sparse),
        size(&all)
    );
}

/// Each entity's frames go out as one chunk per flush (once a second of wall time, and at the
/// end), not a row per frame through Rerun's batcher: every chunk carries its schema in the
/// file and a manifest row in the writer's memory until the footer. Every ragdoll's capsules,
/// rods and bones are instances of one entity per kind, not entities per ragdoll.
#[test]
fn each_entity_gets_one_chunk_per_flush() {
    let path = temp_path("chunks_per_flush.rrd");
    let scene = passive_bending(150); // 2.5 s at 60 Hz, simulated in well under a second
    record_scene(&scene, record::save_to(&path, &scene).unwrap()).unwrap();
    let chunks = decode(&path);
    for entity in [
        "world/ragdolls/capsules",
        "world/ragdolls/rods/centerlines",
        "world/ragdolls/bones/arc",
        "metrics/dislocation_cm",
        "metrics/energy",
    ] {
        let temporal = (chunks.iter())
            .filter(|c| !c.is_static() && c.entity_path().to_string() == format!("/{entity}"))
            .count();
        assert!(
            (1..=2).contains(&temporal),
            "{entity}: {temporal} chunks, not one a flush"
        );
        let frames = frames_with(&chunks, entity, "");
        assert_eq!(frames, (0..=150).collect::<BTreeSet<i64>>(), "{entity}");
    }
    let time_varying: BTreeSet<String> = (chunks.iter())
        .filter(|c| !c.is_static())
        .map(|c| c.entity_path().to_string())
        .collect();
    assert!(
        time_varying.len() <= 16,
        "entities with a chunk per flush: {time_varying:?}"
    );
}

/// `kill -9` leaves a file without a footer that still decodes, with every frame from 0 up to
/// the last flush: the recorder flushes once a second of wall time.
#[test]
fn a_killed_run_keeps_every_frame_up_to_its_last_flush() {
    let path = temp_path("killed.rrd");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_rodlab"))
        .arg("run")
        .arg(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/scenes/ragdoll_drop.toml"
        ))
        .args(["--spine", "rod", "--frames", "600000", "--save"])
        .arg(&path)
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(2500));
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    let chunks = decode_prefix(&path);
    let recorded = frames_with(&chunks, "world/ragdolls/capsules", "translations");
    let last = *recorded.last().expect("a flush within 2.5 s");
    assert_eq!(recorded, (0..=last).step_by(2).collect::<BTreeSet<i64>>());
    // 30 ragdolls, yet as few entities as two: they are instances, not entities
    let time_varying: BTreeSet<String> = (chunks.iter())
        .filter(|c| !c.is_static())
        .map(|c| c.entity_path().to_string())
        .collect();
    assert!(time_varying.len() <= 16, "{time_varying:?}");
}

/// `run --stdout` streams the recording on stdout: the summary goes to stderr, so nothing but
/// the recording is on stdout (a report line there is trailing bytes in the stream).
#[test]
fn stdout_recording_carries_no_report_text() {
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_rodlab"))
        .args([
            "run",
            concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/passive_bending.toml"),
            "--frames",
            "40",
            "--stdout",
        ])
        .output()
        .unwrap();
    assert!(output.status.success());
    let has = |bytes: &[u8], text: &str| bytes.windows(text.len()).any(|w| w == text.as_bytes());
    assert!(
        has(&output.stderr, "state hash"),
        "the summary is on stderr"
    );
    assert!(
        !has(&output.stdout, "state hash"),
        "no summary in the stream"
    );
    assert!(
        !has(&output.stdout, "step profile"),
        "no profile in the stream"
    );
    let path = temp_path("stdout.rrd");
    std::fs::write(&path, &output.stdout).unwrap();
    let chunks = decode(&path);
    assert_eq!(
        frames_with(&chunks, "world/ragdolls/capsules", "translations"),
        (0..=40).collect::<BTreeSet<i64>>()
    );
}
