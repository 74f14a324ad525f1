//! Faults around a run rather than in its scene: a disk that fills while the recording is
//! written, a reader that closes the pipe of the run's reports, and the two SIGTERMs GNU
//! `timeout` sends (one to the child, one to its process group). Each case runs the binary
//! and bounds its time, so a hang fails the test instead of stalling the suite.

use std::collections::BTreeSet;
use std::path::Path;
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

/// `rodlab ARGS` through `sh` with files limited to `blocks` blocks (512 or 1024 bytes, as
/// the shell counts them), SIGXFSZ ignored: every write past the limit fails with EFBIG
/// ("File too large"), as every write to a full disk fails with ENOSPC.
fn run_with_file_limit(blocks: u32, args: &[&str]) -> Child {
    let quoted: Vec<String> = args.iter().map(|a| format!("'{a}'")).collect();
    let script = format!(
        "trap '' XFSZ; ulimit -f {blocks}; exec '{BIN}' {}",
        quoted.join(" ")
    );
    Command::new("sh")
        .args(["-c", &script])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// A recording that cannot be written (the passive-bending run writes 0.7 MB; the limits cut
/// it from its header to near its footer) ends the run within seconds, every time, with an
/// error naming the file and the OS error, and a non-zero exit code.
#[test]
fn a_full_disk_ends_the_run_with_the_os_error_every_time() {
    let out = temp_path("full_disk.rrd");
    let out_text = out.to_str().unwrap();
    for blocks in [1, 16, 64, 150, 300, 450, 600, 690] {
        let child = run_with_file_limit(
            blocks,
            &["run", &scene("passive_bending"), "--save", out_text],
        );
        let what = format!("run with a file limit of {blocks} blocks");
        let output = finish_within(child, Duration::from_secs(20), &what);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{what}: {stderr}");
        assert!(
            stderr.contains("File too large") && stderr.contains(out_text),
            "{what}: {stderr}"
        );
    }
}

/// The main job (`all --out`) fails the same way, for each scene it cannot write.
#[test]
fn a_full_disk_ends_the_main_job_with_the_os_error() {
    let scenes = temp_path("full_disk_scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    std::fs::copy(
        scene("passive_bending"),
        scenes.join("passive_bending.toml"),
    )
    .unwrap();
    let out = temp_path("full_disk_out");
    let child = run_with_file_limit(
        200,
        &[
            "all",
            "--scenes",
            scenes.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let output = finish_within(child, Duration::from_secs(20), "all --out");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("passive_bending.rrd: File too large"),
        "{stderr}"
    );
}

/// A device where every write fails (`/dev/full`, ENOSPC) fails at once, naming the error.
#[test]
fn a_device_that_is_always_full_fails_at_once() {
    if !Path::new("/dev/full").exists() {
        return; // not Linux: the file-limit tests above cover the same path
    }
    let child = Command::new(BIN)
        .args(["run", &scene("passive_bending"), "--force", "--save"])
        .arg("/dev/full")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let output = finish_within(child, Duration::from_secs(20), "run --save /dev/full");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("No space left on device"), "{stderr}");
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
