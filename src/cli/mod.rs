//! Command line: `rodlab` (the main job), `rodlab run SCENE`, `rodlab sweep SCENE`, `rodlab tune
//! [SCENE]`, `rodlab stress`, `rodlab check SCENE...`.
//! `rerun::clap::RerunArgs` is flattened into `run`, so `--save`, `--spawn` and `--connect`
//! behave as in every Rerun example; without any of them a run saves to
//! `recordings/<scene>.rrd`.

use std::path::{Path, PathBuf};

use anyhow::Context as _;
use clap::{parser::ValueSource, ArgMatches, CommandFactory, FromArgMatches};

use crate::scene::Scene;
use crate::shard::Shard;

/// Set when the recording itself goes to stdout (`run --stdout`): the run's reports then go
/// to stderr, so the stream stays a valid .rrd.
static STDOUT_IS_RECORDING: std::sync::atomic::AtomicBool =
    std::sync::atomic::AtomicBool::new(false);

/// Set once a report line could not be written to stdout: its reader went away
/// (`rodlab run ... | head -1`) or its file is full.
static STDOUT_CLOSED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Writes one report line to stdout, or to stderr while stdout carries the recording.
///
/// Reports are a by-product of a run; its recording is what it makes. So a stdout that fails
/// (a closed pipe, EPIPE) stops the printing, never the run: the run goes on and finishes its
/// recording, and the exit code is the run's own (0 when it succeeded), as for a run whose
/// output nobody reads.
pub(crate) fn print_report(line: std::fmt::Arguments) {
    use std::io::Write as _;
    use std::sync::atomic::Ordering::Relaxed;
    if STDOUT_IS_RECORDING.load(Relaxed) {
        print_note(line);
    } else if !STDOUT_CLOSED.load(Relaxed) && writeln!(std::io::stdout().lock(), "{line}").is_err()
    {
        STDOUT_CLOSED.store(true, Relaxed);
    }
}

/// Writes one line to stderr; a stderr that fails is ignored, as for [`print_report`].
pub(crate) fn print_note(line: std::fmt::Arguments) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr().lock(), "{line}");
}

/// A report line ([`print_report`]): stdout, or stderr while stdout carries the recording.
macro_rules! report {
    ($($arg:tt)*) => {
        $crate::cli::print_report(format_args!($($arg)*))
    };
}

/// A line on stderr ([`print_note`]).
macro_rules! note {
    ($($arg:tt)*) => {
        $crate::cli::print_note(format_args!($($arg)*))
    };
}

mod args;
mod benchmarks;
mod layouts;
mod main_job;
mod parse;
mod run;
mod settings_args;
pub mod stop;
mod stress;
mod summary;
mod sweep;
pub mod tune;

pub use args::{Cli, Command, OverrideArgs, SweepArgs};
pub use run::{load_scene, record_kinematics_scene, record_scene, record_scene_from};
pub use summary::print_summary;

use layouts::layouts;
use main_job::{main_job, main_job_outputs, run_all};
use run::{check_output, rerun_sink_given, run_one};
use stress::stress;
use sweep::sweep;

/// The `rodlab` binary: parses the command line and runs the command, inside a thread pool of
/// `--threads` workers when given.
pub fn main() -> anyhow::Result<()> {
    let matches = Cli::command().get_matches();
    let cli = Cli::from_arg_matches(&matches)?;
    let threads = match &cli.command {
        Some(Command::Run { overrides, .. } | Command::All { overrides, .. }) => overrides.threads,
        Some(Command::Sweep(args)) => args.threads,
        Some(Command::Layouts(args)) => args.overrides.threads,
        _ => None,
    };
    match threads {
        None => dispatch(cli, &matches),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n as usize)
            .build()
            .context("cannot start the thread pool")?
            .install(|| dispatch(cli, &matches)),
    }
}

/// Runs the parsed command (inside the thread pool `--threads` asked for, if any).
fn dispatch(cli: Cli, matches: &ArgMatches) -> anyhow::Result<()> {
    if matches!(
        cli.command,
        None | Some(Command::Run { .. } | Command::All { .. })
    ) {
        stop::install()?;
    }
    dispatch_command(cli, matches)?;
    if let Some(code) = stop::exit_code() {
        note!(
            "stopped by {}: the recording is complete up to there",
            stop::signal_name()
        );
        std::process::exit(code);
    }
    Ok(())
}

fn dispatch_command(cli: Cli, matches: &ArgMatches) -> anyhow::Result<()> {
    match cli.command {
        None => main_job(),
        Some(Command::Sweep(args)) => {
            // without named methods an unset joint list is both flavours
            let joints = match args.joint.is_empty() && args.methods.is_empty() {
                true => crate::sweep::SweepConfig::default().joints,
                false => args.joint,
            };
            let config = crate::sweep::SweepConfig {
                joints,
                methods: args.methods,
                spines: args.spines,
                bend_twist: args.bend_twist,
                settings: args.settings.into(),
                frames: args.frames,
                repeats: args.repeats,
            };
            let shard = args.shard.unwrap_or(Shard::ALL);
            sweep(&args.scene, &config, args.peer.as_deref(), shard, &args.out).map(|_| ())
        }
        Some(Command::All {
            scenes,
            out,
            overrides,
        }) => run_all(&scenes, &out, &(&overrides).into()),
        Some(Command::Run {
            scene,
            variant,
            record_from,
            force,
            overrides,
            rerun,
        }) => {
            let sub = matches.subcommand_matches("run").expect("run subcommand");
            if let Some(out) = sub.get_one::<PathBuf>("save") {
                check_output(out, &scene, force)?;
            }
            let scene = load_scene(&scene, variant.as_deref(), &(&overrides).into())?;
            let save = sub.get_one::<PathBuf>("save").map(PathBuf::as_path);
            if matches!(sub.value_source("stdout"), Some(ValueSource::CommandLine)) {
                STDOUT_IS_RECORDING.store(true, std::sync::atomic::Ordering::Relaxed);
            }
            run_one(&scene, record_from, &rerun, rerun_sink_given(sub), save)
        }
        Some(Command::Check { scenes }) => check(&scenes),
        Some(Command::Outputs) => {
            for file in main_job_outputs(Path::new("scenes"), Path::new("recordings"))? {
                report!("{}", file.display());
            }
            Ok(())
        }
        Some(Command::Merge {
            shards,
            out,
            machine,
        }) => sweep::merge(&shards, &machine, &out),
        Some(Command::Methods) => {
            for method in crate::scene::Method::ALL {
                report!("# method = \"{method}\"{}", method.settings_toml());
            }
            Ok(())
        }
        Some(Command::Benchmarks { criterion, out }) => {
            let path = benchmarks::write(&criterion, &out)?;
            report!("-> {}", path.display());
            Ok(())
        }
        Some(Command::Settings) => {
            report!("{}", crate::scene::settings_table());
            Ok(())
        }
        Some(Command::Tune(args)) => tune::tune(&args),
        Some(Command::Stress { out }) => stress(&out),
        Some(Command::Layouts(args)) => layouts(&args),
    }
}

fn check(paths: &[PathBuf]) -> anyhow::Result<()> {
    for path in paths {
        let scene = Scene::load(path)?;
        let lab = scene.build()?;
        report!(
            "{}: ok ({} bodies, {} constraints, {} ragdolls, {} frames at dt {} s, {} substep(s) x {} iterations, {} solver)",
            path.display(),
            lab.world.bodies.len(),
            lab.world.constraints.len(),
            lab.ragdolls.len(),
            scene.def.frames,
            scene.def.dt,
            scene.def.substeps,
            scene.def.iterations,
            scene.def.solver
        );
    }
    Ok(())
}
