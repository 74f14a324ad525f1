//! The command line: `run --help` fits on a screen, every subcommand shows an example, and
//! `--set key=value` reaches any setting the flags do, checked against the same bounds.

use clap::Parser;
use rodlab::cli::{Cli, Command};
use rodlab::sim::Overrides;

/// The overrides `rodlab run ARGS` asks for, or clap's error text.
fn run_overrides(args: &[&str]) -> Result<Overrides, String> {
    let argv = ["rodlab", "run", "scene.toml"].iter().chain(args);
    match Cli::try_parse_from(argv)
        .map_err(|e| e.to_string())?
        .command
    {
        Some(Command::Run { overrides, .. }) => Ok(Overrides::from(&overrides)),
        other => panic!("parsed as {other:?}"),
    }
}

/// `--set` gives the same overrides as the flags, for a method setting, a choice and a rod
/// setting; the last of two values wins, and an alpha and a stiffness replace each other.
#[test]
fn set_reaches_what_the_flags_do() {
    let flags = run_overrides(&[
        "--contact-hertz",
        "90",
        "--joint",
        "exact",
        "--bend-stiffness",
        "5",
        "--sleep",
        "true",
    ])
    .unwrap();
    let set = run_overrides(&[
        "--set",
        "contact_hertz=30",
        "--set",
        "contact_hertz=90",
        "--set",
        "joint_flavour=exact",
        "--set",
        "alpha_b=0.1",
        "--set",
        "bend_stiffness=5",
        "--set",
        "sleep=true",
    ])
    .unwrap();
    assert_eq!(set, flags);
    assert_ne!(set, Overrides::default());
}

/// A value the scene file could not hold is refused at parse time, naming the key, the bound
/// and the unit; so are an unknown key, and a pair without `=`.
#[test]
fn set_refuses_what_a_scene_file_refuses() {
    for (arg, says) in [
        ("contact_hertz=-1", "must be 0 or more (Hz), got -1"),
        ("iterations=0", "iterations=0"),
        ("solver=fast", "solver=fast"),
        ("alpha_b=2", "lie in [0, 1]"),
        ("colour=red", "unknown key `colour`"),
        ("sleep", "is not KEY=VALUE"),
    ] {
        let message = run_overrides(&["--set", arg]).unwrap_err();
        assert!(message.contains(says), "--set {arg}: {message}");
    }
}

/// `rodlab run --help` lists at most 20 options, and every subcommand's help ends with an
/// example of itself.
#[test]
fn help_is_short_and_shows_examples() {
    let help = |sub: &str| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_rodlab"))
            .args([sub, "--help"])
            .output()
            .unwrap();
        assert!(out.status.success(), "{sub} --help");
        String::from_utf8(out.stdout).unwrap()
    };
    let options = (help("run").lines())
        .filter(|l| l.trim_start().starts_with('-'))
        .count();
    assert!(options <= 20, "run --help lists {options} options");
    for sub in [
        "all",
        "run",
        "sweep",
        "tune",
        "stress",
        "layouts",
        "check",
        "outputs",
        "methods",
        "settings",
        "merge",
        "benchmarks",
    ] {
        let text = help(sub);
        assert!(
            text.contains(&format!("Example: rodlab {sub}")),
            "{sub} --help has no example:\n{text}"
        );
    }
}
