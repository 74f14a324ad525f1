//! The command line's settings meet the very bounds a scene file's do (one set of bounds for
//! every source of a setting): a value the file could not hold is refused with an error naming
//! the flag, before anything runs, and a value at the bound is accepted from both.

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use rodlab::cli::load_scene;
use rodlab::scene::bounds::{MAX_DT, MAX_FRAMES, MAX_ITERATIONS, MAX_SUBSTEPS};
use rodlab::scene::Scene;
use rodlab::sim::Overrides;

use crate::common::temp_path;

fn scene(name: &str) -> String {
    format!("{}/scenes/{name}.toml", env!("CARGO_MANIFEST_DIR"))
}

/// `rodlab ARGS`, which must end within 20 s.
fn rodlab(args: &[&str]) -> std::process::Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_rodlab"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > Duration::from_secs(20) {
            child.kill().unwrap();
            panic!("rodlab {args:?} still running after 20 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// Each override past its bound (a frame that never ends, 4 GB of per-frame storage, a time
/// step past the file's bound, a hundred thousand threads) is refused at once, naming its
/// flag, and nothing is written.
#[test]
fn overrides_past_the_scene_bounds_are_refused_naming_the_flag() {
    let out = temp_path("refused_override.rrd");
    let _ = std::fs::remove_file(&out);
    let drop = scene("ragdoll_drop");
    for (flag, value) in [
        ("--iterations", "4294967295"),
        ("--substeps", "4294967295"),
        ("--frames", "1000000000"),
        ("--dt", "2"),
        ("--threads", "100000"),
        ("--record-every", "4294967295"),
        ("--contact-extra-sweeps", "4294967295"),
    ] {
        let output = rodlab(&["run", &drop, flag, value, "--save", out.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{flag} {value} accepted");
        assert!(stderr.contains(flag), "{flag} {value}: {stderr}");
        assert!(!out.exists(), "{flag} {value}: a recording was written");
    }
}

/// The sweep's lists meet the same bounds before its first run.
#[test]
fn sweep_values_past_the_scene_bounds_are_refused_naming_the_flag() {
    let out = temp_path("refused_sweep");
    let bending = scene("passive_bending");
    for (flag, value) in [("--iterations", "4,4294967295"), ("--dt", "0.01,2")] {
        let args = [
            "sweep",
            &bending,
            flag,
            value,
            "--out",
            out.to_str().unwrap(),
        ];
        let output = rodlab(&args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{flag} {value} accepted");
        assert!(stderr.contains(flag), "{flag} {value}: {stderr}");
    }
}

/// A setting's field, its bound, a value past it, and the overrides that set a value.
type BoundCase = (&'static str, String, String, fn(&str) -> Overrides);

/// At and past each bound, the command line and the scene file agree: the bound itself is
/// accepted from both, one past it refused by both, the file's error naming the field and the
/// command line's the flag.
#[test]
fn the_command_line_and_the_file_share_one_set_of_bounds() {
    let path = scene("passive_bending");
    let text = std::fs::read_to_string(&path).unwrap();
    let cases: [BoundCase; 4] = [
        (
            "iterations",
            MAX_ITERATIONS.to_string(),
            (MAX_ITERATIONS + 1).to_string(),
            |v| Overrides {
                iterations: Some(v.parse().unwrap()),
                ..Default::default()
            },
        ),
        (
            "substeps",
            MAX_SUBSTEPS.to_string(),
            (MAX_SUBSTEPS + 1).to_string(),
            |v| Overrides {
                substeps: Some(v.parse().unwrap()),
                ..Default::default()
            },
        ),
        (
            "frames",
            MAX_FRAMES.to_string(),
            (MAX_FRAMES + 1).to_string(),
            |v| Overrides {
                frames: Some(v.parse().unwrap()),
                ..Default::default()
            },
        ),
        (
            "dt",
            format!("{MAX_DT:?}"),
            format!("{:?}", MAX_DT * 1.5),
            |v| Overrides {
                dt: Some(v.parse().unwrap()),
                ..Default::default()
            },
        ),
    ];
    for (field, at_bound, past, overrides) in cases {
        let flag = format!("--{field}");
        // the file's own line replaces the scene's (a TOML key may appear once)
        let stripped: String = (text.lines())
            .filter(|l| !l.starts_with(&format!("{field} ")))
            .map(|l| format!("{l}\n"))
            .collect();
        let file =
            |value: &str| Scene::parse("scenes/x.toml", &format!("{field} = {value}\n{stripped}"));
        assert!(file(&at_bound).is_ok(), "{field} = {at_bound} refused");
        let refused = file(&past).expect_err("past the bound").to_string();
        assert!(refused.contains(&format!(": {field}: ")), "{refused}");
        assert!(load_scene(path.as_ref(), None, &overrides(&at_bound)).is_ok());
        let refused = load_scene(path.as_ref(), None, &overrides(&past))
            .expect_err("past the bound")
            .to_string();
        assert!(refused.contains(&format!("{flag}: ")), "{refused}");
    }
}

/// `--frames` below a scene's `ci_frames` (the main job's shorter run) is a shorter run, not
/// an error: the rain's 60 become 10.
#[test]
fn frames_below_ci_frames_run_that_many() {
    let overrides = Overrides {
        frames: Some(10),
        ..Default::default()
    };
    let rain = load_scene(scene("ragdoll_rain").as_ref(), None, &overrides).unwrap();
    assert_eq!((rain.def.frames, rain.def.ci_frames), (10, Some(10)));
}
