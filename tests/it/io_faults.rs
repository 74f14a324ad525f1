//! Faults around a run rather than in its scene: a disk that fills while the recording is
//! written, a reader that closes the pipe of the run's reports, and the two SIGTERMs GNU
//! `timeout` sends (one to the child, one to its process group). Each case runs the binary
//! and bounds its time, so a hang fails the test instead of stalling the suite.

use std::collections::BTreeSet;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::common::{decode, frames_with, static_texts, temp_path};

const BIN: &str = env!("CARGO_BIN_EXE_rodlab");

fn scene(name: &str) -> String {
    format!("{}/scenes/{name}.toml", env!("CARGO_MANIFEST_DIR"))
}

/// Waits for `child` at most `limit`; a child still running then is killed and fails the test.
fn finish_within(mut child: Child, limit: Duration, what: &str) -> Output {
    let started = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > limit {
            child.kill().unwrap();
            let output = child.wait_with_output().unwrap();
            panic!(
                "{what}: still running after {limit:?}; stderr:\n{}",
                String::from_utf8_lossy(&output.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// A closed stdout (`rodlab run ... | head -1`; here the pipe's reader is gone before the
/// first line) stops the printing, not the run: no panic, exit code 0, and the recording holds
/// every frame and its footer's state hash.
#[test]
fn a_closed_stdout_stops_the_reports_and_the_run_finishes_its_recording() {
    let path = temp_path("closed_stdout.rrd");
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    // the controllability scene prints a row of residuals every 30 of its 300 frames
    let child = Command::new(BIN)
        .args(["run", &scene("controllability"), "--save"])
        .arg(&path)
        .stdout(writer)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let output = finish_within(child, Duration::from_secs(60), "run | head -1");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let chunks = decode(&path);
    let frames = frames_with(&chunks, "metrics/dislocation_cm", "scalars");
    assert_eq!(frames, (0..=300).collect::<BTreeSet<i64>>());
    assert_eq!(static_texts(&chunks, "state_hash", "text").len(), 1);
}

/// Two SIGTERMs 10 ms apart (GNU `timeout` sends one to the child and one to its group), both
/// within a frame (100 substeps make a frame long), are one request to stop: the run stops at
/// the frame's end, prints its summary, finishes its recording (footer included) and exits
/// with 143; the second does not cut it short.
#[test]
fn two_sigterms_close_together_stop_the_run_once() {
    for attempt in 0..3 {
        let path = temp_path(&format!("two_sigterms_{attempt}.rrd"));
        let child = Command::new(BIN)
            .args(["run", &scene("ragdoll_drop")])
            .args(["--spine", "rod", "--frames", "600000", "--substeps", "100"])
            .args(["--record-every", "1", "--save"])
            .arg(&path)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(1200));
        let pid = child.id();
        let kills = format!("kill -TERM {pid}; sleep 0.01; kill -TERM {pid}");
        let sent = Command::new("sh").args(["-c", &kills]).status().unwrap();
        assert!(sent.success());
        let output = finish_within(child, Duration::from_secs(30), "run after two SIGTERMs");
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert_eq!(
            output.status.code(),
            Some(143),
            "attempt {attempt}: {stdout}"
        );
        let stopped = stdout
            .lines()
            .find_map(|l| l.trim().strip_prefix("stopped by SIGTERM after "))
            .unwrap_or_else(|| panic!("attempt {attempt}: no summary in {stdout}"));
        let frames: i64 = stopped.split(' ').next().unwrap().parse().unwrap();
        // decoded strictly: the footer was written
        let chunks = decode(&path);
        let recorded = frames_with(&chunks, "world/ragdolls/capsules", "translations");
        assert_eq!(recorded, (0..=frames).collect::<BTreeSet<i64>>());
        assert_eq!(static_texts(&chunks, "state_hash", "text").len(), 1);
    }
}
