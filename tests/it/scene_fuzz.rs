//! A seeded mutation fuzzer over `scenes/*.toml`: 2400 mutants (numbers swapped for NaN,
//! infinities, huge, negative and wrong-typed values; lines deleted, doubled or renamed; files
//! cut short or salted with punctuation), each checked and, if accepted, built and run for 5
//! frames (scenes of more than 100 ragdolls are checked only, to stay under a minute). Nothing
//! may panic or hang, and every rejection must name the file and a line.

use std::cell::Cell;
use std::io::Write;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Once};
use std::time::{Duration, Instant};

use rodlab::scene::Scene;
use rodlab::sim::{self, NoObserver};

const MUTANTS: usize = 2400;

thread_local! {
    static QUIET: Cell<bool> = const { Cell::new(false) };
}

/// Silences panic messages on this thread while it lives (the process's panic hook is wrapped
/// once, and prints for every other thread as before).
struct QuietPanics;

impl QuietPanics {
    fn on_this_thread() -> Self {
        static WRAP: Once = Once::new();
        WRAP.call_once(|| {
            let previous = std::panic::take_hook();
            std::panic::set_hook(Box::new(move |info| {
                if !QUIET.with(Cell::get) {
                    previous(info);
                }
            }));
        });
        QUIET.with(|q| q.set(true));
        QuietPanics
    }
}

impl Drop for QuietPanics {
    fn drop(&mut self) {
        QUIET.with(|q| q.set(false));
    }
}

/// Ends the process with a message (written past the test harness's capture) if it is still
/// alive after `limit`; dropping it stands it down.
struct Watchdog(Arc<AtomicBool>);

impl Watchdog {
    fn start(limit: Duration, message: impl Fn() -> String + Send + 'static) -> Self {
        let done = Arc::new(AtomicBool::new(false));
        let seen = done.clone();
        std::thread::spawn(move || {
            let started = Instant::now();
            while started.elapsed() < limit {
                std::thread::sleep(Duration::from_millis(200));
                if seen.load(Ordering::Relaxed) {
                    return;
                }
            }
            let _ = writeln!(std::io::stderr(), "{}", message());
            std::process::exit(101);
        });
        Watchdog(done)
    }
}

impl Drop for Watchdog {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Relaxed);
    }
}

/// A small deterministic generator (64-bit LCG, Knuth's MMIX constants).
struct Random(u64);

impl Random {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 33
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

const VALUES: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "1e30",
    "-1e30",
    "3.4e38",
    "1e-30",
    "0",
    "-0.0",
    "-1",
    "0.5",
    "2",
    "1e9",
    "2147483647",
    "4294967295",
    "18446744073709551615",
    "100000",
    "\"x\"",
    "true",
    "[]",
    "[1.0]",
    "{}",
];

/// Byte spans of the number literals in `text`.
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let starts = bytes[i].is_ascii_digit()
            || (bytes[i] == b'-' && bytes.get(i + 1).is_some_and(u8::is_ascii_digit));
        let in_word = i > 0 && (bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_');
        if starts && !in_word {
            let start = i;
            i += 1;
            while i < bytes.len()
                && (bytes[i].is_ascii_alphanumeric() || b".+-_".contains(&bytes[i]))
            {
                i += 1;
            }
            spans.push((start, i));
        } else {
            i += 1;
        }
    }
    spans
}

fn mutate(text: &str, random: &mut Random) -> String {
    let mut text = text.to_string();
    for _ in 0..1 + random.below(3) {
        let lines: Vec<&str> = text.lines().collect();
        text = match random.below(10) {
            0..=4 => {
                let spans = numbers(&text);
                if spans.is_empty() {
                    continue;
                }
                let (a, b) = spans[random.below(spans.len())];
                let value = VALUES[random.below(VALUES.len())];
                format!("{}{value}{}", &text[..a], &text[b..])
            }
            5 => {
                let i = random.below(lines.len());
                let mut out: Vec<&str> = lines.clone();
                out.remove(i);
                out.join("\n")
            }
            6 => {
                let i = random.below(lines.len());
                let mut out: Vec<&str> = lines.clone();
                out.insert(i, lines[i]);
                out.join("\n")
            }
            7 => {
                let i = random.below(lines.len());
                let renamed = lines[i].replacen(" =", "x =", 1);
                let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
                out[i] = renamed;
                out.join("\n")
            }
            8 => {
                let mut cut = random.below(text.len());
                while !text.is_char_boundary(cut) {
                    cut -= 1;
                }
                text[..cut].to_string()
            }
            _ => {
                let mut at = random.below(text.len());
                while !text.is_char_boundary(at) {
                    at -= 1;
                }
                let salt = ["=", "[", "]", "\"", ",", "#", "{", "."][random.below(8)];
                format!("{}{salt}{}", &text[..at], &text[at..])
            }
        };
    }
    text
}

#[test]
fn mutated_scenes_never_panic_and_every_rejection_names_a_line() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes");
    let mut scenes: Vec<(String, String)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .map(|p| {
            let name = format!("scenes/{}", p.file_name().unwrap().to_string_lossy());
            (name, std::fs::read_to_string(&p).unwrap())
        })
        .collect();
    scenes.sort();
    // This thread's panics are counted, not printed; other tests' panics (the test binary
    // runs them alongside) still print.
    let quiet = QuietPanics::on_this_thread();
    // A mutant that never finishes (an unbounded count, say) ends the test binary
    // instead of hanging it. The watchdog stands down when this test ends, pass or fail: the
    // binary's other tests keep running long after, and must not be ended by it.
    static CURRENT: AtomicUsize = AtomicUsize::new(0);
    let _watchdog = Watchdog::start(std::time::Duration::from_secs(120), || {
        format!(
            "mutant {} still running after 120 s",
            CURRENT.load(Ordering::Relaxed)
        )
    });
    let mut random = Random(2026);
    let (mut rejected, mut ran, mut checked_only) = (0, 0, 0);
    let mut failures: Vec<String> = Vec::new();
    let started = std::time::Instant::now();
    for i in 0..MUTANTS {
        CURRENT.store(i, Ordering::Relaxed);
        let (name, original) = &scenes[i % scenes.len()];
        let text = mutate(original, &mut random);
        let parsed = catch_unwind(|| Scene::parse(name, &text));
        let scene = match parsed {
            Err(_) => {
                failures.push(format!("mutant {i} of {name}: check panicked"));
                continue;
            }
            Ok(Err(e)) => {
                let message = e.to_string();
                let names_line = message
                    .strip_prefix(&format!("{name}:"))
                    .and_then(|rest| rest.split_once(':'))
                    .is_some_and(|(line, _)| line.parse::<usize>().is_ok_and(|l| l >= 1));
                if !names_line {
                    failures.push(format!("mutant {i} of {name}: no line in \"{message}\""));
                }
                rejected += 1;
                continue;
            }
            Ok(Ok(scene)) => scene,
        };
        if scene.def.ragdoll.len() > 100 {
            checked_only += 1;
            continue;
        }
        let outcome = catch_unwind(AssertUnwindSafe(|| -> Result<(), String> {
            let mut lab = scene.build().map_err(|e| e.to_string())?;
            sim::run(&mut lab, 5, &mut NoObserver).map_err(|e| format!("{e:#}"))?;
            Ok(())
        }));
        match outcome {
            Err(_) => failures.push(format!("mutant {i} of {name}: the run panicked")),
            Ok(Err(message)) if !message.contains(name.as_str()) && message.contains("scenes/") => {
                failures.push(format!("mutant {i} of {name}: {message}"));
            }
            Ok(_) => ran += 1,
        }
    }
    drop(quiet); // the verdict below must print if it fails
    println!(
        "{MUTANTS} mutants in {:.1} s: {rejected} rejected, {ran} run for 5 frames, \
         {checked_only} checked only",
        started.elapsed().as_secs_f64()
    );
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert!(
        rejected >= 200 && ran >= 200,
        "{rejected} rejected, {ran} run"
    );
}
