//! Command line: `rodlab` (the main job), `rodlab run SCENE`, `rodlab sweep SCENE`, `rodlab tune
//! [SCENE]`, `rodlab stress`, `rodlab check SCENE...`.
//! `rerun::clap::RerunArgs` is flattened into `run`, so `--save`, `--spawn` and `--connect`
//! behave as in every Rerun example; without any of them a run saves to
//! `recordings/<scene>.rrd`.

use std::path::{Path, PathBuf};

use anyhow::Context as _;
use clap::{
    parser::ValueSource, ArgMatches, Args, CommandFactory, FromArgMatches, Parser, Subcommand,
};

use crate::constraint::{JointFlavour, TwistMode};
use crate::lab::Lab;
use crate::metrics::FrameMetrics;
use crate::ragdoll::SpineKind;
use crate::record::{self, Recorder};
use crate::scene::Scene;
use crate::shard::Shard;
use crate::sim::{self, Observer, Overrides, RunReport};
use crate::world::{SimulationError, SolverKind};

pub mod stop;
pub mod tune;

/// Set when the recording itself goes to stdout (`run --stdout`): the run's reports then go
/// to stderr, so the stream stays a valid .rrd.
static STDOUT_IS_RECORDING: std::sync::atomic::AtomicBool =
    std::sync::atomic::AtomicBool::new(false);

/// `println!`, or `eprintln!` while stdout carries the recording.
macro_rules! report {
    ($($arg:tt)*) => {
        if STDOUT_IS_RECORDING.load(std::sync::atomic::Ordering::Relaxed) {
            eprintln!($($arg)*)
        } else {
            println!($($arg)*)
        }
    };
}

#[derive(Debug, Parser)]
#[command(
    name = "rodlab",
    version,
    about = "Rod constraints for simplified ragdolls (SCA 2013), recorded to Rerun"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
}

// The doc comments are `--help` text, where `<out>` is a placeholder, not HTML.
#[allow(rustdoc::invalid_html_tags)]
#[derive(Debug, Subcommand)]
pub enum Command {
    /// The main job: every scene in a folder -> <out>/<scene>.rrd, plus a residual summary
    /// (a scene with `ci_frames` runs that many frames, unless --frames).
    All {
        #[arg(long, default_value = "scenes")]
        scenes: PathBuf,
        #[arg(long, default_value = "recordings")]
        out: PathBuf,
        #[command(flatten)]
        overrides: OverrideArgs,
    },
    /// Runs one scene and records it.
    Run {
        scene: PathBuf,
        /// Run the scene's `[[variant]]` of this name (its settings, then the overrides below),
        /// recorded as <scene>_<variant>.
        #[arg(long)]
        variant: Option<String>,
        /// Record only the frames from this simulated time on (s; the run still starts at 0):
        /// a smaller file of how a long run ends.
        #[arg(long, value_parser = non_negative, default_value_t = 0.0)]
        record_from: f32,
        /// Let --save write over an existing file that is not an .rrd (never over the scene).
        #[arg(long)]
        force: bool,
        #[command(flatten)]
        overrides: OverrideArgs,
        #[command(flatten)]
        rerun: rerun::clap::RerunArgs,
    },
    /// Speed against accuracy: runs SCENE headless for every spine, joint flavour, time step
    /// and iteration count -> <out>/<scene>_sweep.csv, .svg (chart) and .rrd.
    Sweep(SweepArgs),
    /// Tuning by eye: every combination of bend and twist settings (and iteration counts) as
    /// one copy of the scene's rod-spine ragdoll on a labelled grid -> <out>/tune.rrd, .csv,
    /// .svg, .png; or, with --match-psi / --match, the settings that settle at a bend.
    Tune(tune::TuneArgs),
    /// The stability suite: every case for every method, a verdict each -> <out>/stress.md,
    /// <out>/stress.csv, and a recording of every run that is not stable (<out>/stress/).
    Stress {
        #[arg(long, default_value = "recordings")]
        out: PathBuf,
    },
    /// Validates scene files without running them.
    Check {
        #[arg(required = true)]
        scenes: Vec<PathBuf>,
    },
    /// Lists the files the main job writes, one per line (what CI checks and archives).
    Outputs,
}

#[derive(Debug, Clone, Args)]
pub struct SweepArgs {
    pub scene: PathBuf,
    /// Iteration counts, comma separated.
    #[arg(long, value_delimiter = ',', default_value = "1,2,4,8,16,32",
          value_parser = clap::value_parser!(u32).range(1..))]
    pub iterations: Vec<u32>,
    /// Spines, comma separated.
    #[arg(long, value_delimiter = ',', default_value = "chain3,rod,single",
          value_parser = parse_choice::<SpineKind>)]
    pub spines: Vec<SpineKind>,
    /// Joint flavours, comma separated.
    #[arg(long, value_delimiter = ',', default_value = "cheap,exact",
          value_parser = parse_choice::<JointFlavour>)]
    pub joint: Vec<JointFlavour>,
    /// Time steps (s), comma separated; default the scene's.
    #[arg(long, value_delimiter = ',', value_parser = positive_seconds)]
    pub dt: Vec<f32>,
    /// Substeps per frame, comma separated (each substep runs the iterations).
    #[arg(long, value_delimiter = ',', default_value = "1",
          value_parser = clap::value_parser!(u32).range(1..))]
    pub substeps: Vec<u32>,
    /// Row solvers, comma separated: scalar, simd.
    #[arg(long, value_delimiter = ',', default_value = "scalar",
          value_parser = parse_choice::<SolverKind>)]
    pub solver: Vec<SolverKind>,
    /// Contact warm-start fractions (0 to 1), comma separated; default the scene's.
    #[arg(long, value_delimiter = ',', value_parser = unit_interval)]
    pub contact_warm_start: Vec<f32>,
    /// Soft-contact frequencies (Hz, 0: hard), comma separated; default the scene's.
    #[arg(long, value_delimiter = ',', value_parser = non_negative)]
    pub contact_hertz: Vec<f32>,
    /// Stacking rates (1/m, 0: the paper's contacts), comma separated; default the scene's.
    #[arg(long, value_delimiter = ',', value_parser = stacking_rate)]
    pub contact_stacking: Vec<f32>,
    /// Worker threads of the solver; default rayon's (one per core).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    pub threads: Option<u64>,
    /// Frames per run; default the scene's.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub frames: Option<u32>,
    /// Runs per combination, pooled for the median step time.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..))]
    pub repeats: u32,
    /// Another engine measured the same way (rapier).
    #[arg(long)]
    pub peer: Option<String>,
    /// Run only shard I of N of the combinations (I/N, e.g. 2/3; combination k goes to shard
    /// k mod N + 1); outputs get a _shardIofN suffix.
    #[arg(long, value_parser = |s: &str| s.parse::<crate::shard::Shard>())]
    pub shard: Option<crate::shard::Shard>,
    #[arg(long, default_value = "recordings")]
    pub out: PathBuf,
}

#[derive(Debug, Clone, Args)]
pub struct OverrideArgs {
    /// Solver iterations per substep (per frame with one substep).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub iterations: Option<u32>,
    /// Substeps per frame, each of dt / N with all the iterations.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub substeps: Option<u32>,
    /// Row solver: scalar or simd.
    #[arg(long, value_parser = parse_choice::<SolverKind>)]
    pub solver: Option<SolverKind>,
    /// Sleeping of still islands: true or false (default: the scene's `sleep`).
    #[arg(long)]
    pub sleep: Option<bool>,
    /// Fastest push out of deep contact overlap (m/s; inf: at once).
    #[arg(long, value_parser = positive_speed)]
    pub contact_push_speed: Option<f32>,
    /// Fraction of their last impulses contacts start each substep with (0 to 1; default: the
    /// scene's `contact_warm_start`).
    #[arg(long, value_parser = unit_interval)]
    pub contact_warm_start: Option<f32>,
    /// Soft contacts' natural frequency (Hz; 0: hard, the paper's; default the scene's).
    #[arg(long, value_parser = non_negative)]
    pub contact_hertz: Option<f32>,
    /// Soft contacts' damping ratio (default the scene's).
    #[arg(long, value_parser = non_negative)]
    pub contact_damping_ratio: Option<f32>,
    /// Stacking (1/m): in a contact the lower body counts e^(k dh) times heavier, dh the
    /// other's height above it (0: the paper's contact; default the scene's `contact_stacking`).
    #[arg(long, value_parser = stacking_rate)]
    pub contact_stacking: Option<f32>,
    /// Joint damping, a dashpot across every joint (N m s/rad; 0: none, the paper's; default
    /// the scene's `joint_damping`).
    #[arg(long, value_parser = non_negative)]
    pub joint_damping: Option<f32>,
    /// Worker threads of the solver; default rayon's (one per core).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    pub threads: Option<u64>,
    /// Time step (s).
    #[arg(long, value_parser = positive_seconds)]
    pub dt: Option<f32>,
    /// Frames to simulate.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub frames: Option<u32>,
    /// Spine of every ragdoll: chain3, rod or single.
    #[arg(long, value_parser = parse_choice::<SpineKind>)]
    pub spine: Option<SpineKind>,
    /// Ball-and-socket solver: cheap or exact.
    #[arg(long, value_parser = parse_choice::<JointFlavour>)]
    pub joint: Option<JointFlavour>,
    /// Rod bending relaxation alpha_b in [0, 1].
    #[arg(long, value_parser = unit_interval)]
    pub alpha_b: Option<f32>,
    /// Rod twisting relaxation alpha_t in [0, 1].
    #[arg(long, value_parser = unit_interval)]
    pub alpha_t: Option<f32>,
    /// Rod bending stiffness (N m/rad), solved in compliance form instead of alpha_b: the
    /// same stiffness at any iteration count, time step or substep count.
    #[arg(long, value_parser = positive_stiffness, conflicts_with = "alpha_b")]
    pub bend_stiffness: Option<f32>,
    /// Damping of the rod's bend rate (N m s/rad), with a bending stiffness.
    #[arg(long, value_parser = non_negative)]
    pub bend_damping: Option<f32>,
    /// Rod twisting stiffness (N m/rad), instead of alpha_t.
    #[arg(long, value_parser = positive_stiffness, conflicts_with = "alpha_t")]
    pub twist_stiffness: Option<f32>,
    /// Damping of the rod's twist rate (N m s/rad), with a twisting stiffness.
    #[arg(long, value_parser = non_negative)]
    pub twist_damping: Option<f32>,
    /// Rod twist measure: exact or paper.
    #[arg(long, value_parser = parse_choice::<TwistMode>)]
    pub twist: Option<TwistMode>,
    /// Record every N-th frame (frames 0, N, 2N, ...): a smaller file of a long run.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub record_every: Option<u32>,
}

/// Parses a choice the way scene files spell it (the enum's serde names).
pub(crate) fn parse_choice<T: serde::de::DeserializeOwned>(s: &str) -> Result<T, String> {
    use serde::de::IntoDeserializer;
    T::deserialize(s.into_deserializer())
        .map_err(|e: serde::de::value::Error| e.to_string().replace('`', "\""))
}

fn unit_interval(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if (0.0..=1.0).contains(&v) => Ok(v),
        Ok(v) => Err(format!("must lie in [0, 1], got {v}")),
        Err(e) => Err(e.to_string()),
    }
}

fn non_negative(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v >= 0.0 && v.is_finite() => Ok(v),
        Ok(v) => Err(format!("must be 0 or more, got {v}")),
        Err(e) => Err(e.to_string()),
    }
}

fn positive_seconds(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v > 0.0 && v.is_finite() => Ok(v),
        Ok(v) => Err(format!("must be a positive number of seconds, got {v}")),
        Err(e) => Err(e.to_string()),
    }
}

fn positive_stiffness(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v > 0.0 && v.is_finite() => Ok(v),
        Ok(v) => Err(format!("must be a positive stiffness in N m/rad, got {v}")),
        Err(e) => Err(e.to_string()),
    }
}

fn positive_speed(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v > 0.0 => Ok(v),
        Ok(v) => Err(format!("must be a positive speed in m/s (or inf), got {v}")),
        Err(e) => Err(e.to_string()),
    }
}

fn stacking_rate(s: &str) -> Result<f32, String> {
    let max = crate::scene::MAX_CONTACT_STACKING;
    match s.parse::<f32>() {
        Ok(v) if (0.0..=max).contains(&v) => Ok(v),
        Ok(v) => Err(format!("must be a rate from 0 to {max} per metre, got {v}")),
        Err(e) => Err(e.to_string()),
    }
}

impl From<&OverrideArgs> for Overrides {
    fn from(a: &OverrideArgs) -> Self {
        Overrides {
            iterations: a.iterations,
            substeps: a.substeps,
            solver: a.solver,
            sleep: a.sleep,
            contact_push_speed: a.contact_push_speed,
            contact_warm_start: a.contact_warm_start,
            contact_hertz: a.contact_hertz,
            contact_damping_ratio: a.contact_damping_ratio,
            contact_stacking: a.contact_stacking,
            joint_damping: a.joint_damping,
            dt: a.dt,
            frames: a.frames,
            spine: a.spine,
            joint_flavour: a.joint,
            alpha_b: a.alpha_b,
            alpha_t: a.alpha_t,
            bend_stiffness: a.bend_stiffness,
            bend_damping: a.bend_damping,
            twist_stiffness: a.twist_stiffness,
            twist_damping: a.twist_damping,
            twist: a.twist,
            record_every: a.record_every,
        }
    }
}

pub fn main() -> anyhow::Result<()> {
    let matches = Cli::command().get_matches();
    let cli = Cli::from_arg_matches(&matches)?;
    let threads = match &cli.command {
        Some(Command::Run { overrides, .. } | Command::All { overrides, .. }) => overrides.threads,
        Some(Command::Sweep(args)) => args.threads,
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
        eprintln!(
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
            let config = crate::sweep::SweepConfig {
                iterations: args.iterations,
                spines: args.spines,
                joints: args.joint,
                dts: args.dt,
                substeps: args.substeps,
                solvers: args.solver,
                warm_starts: args.contact_warm_start,
                contact_hertz: args.contact_hertz,
                contact_stacking: args.contact_stacking,
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
                println!("{}", file.display());
            }
            Ok(())
        }
        Some(Command::Tune(args)) => tune::tune(&args),
        Some(Command::Stress { out }) => stress(&out),
    }
}

/// The main job: every scene recorded, then the passive-bending sweep.
/// Scenes the main job sweeps, besides recording every scene.
const SWEPT_SCENES: [&str; 2] = ["passive_bending", "ragdoll_drop"];

/// The files [`main_job`] writes: every scene's recordings (one per spine and variant), each
/// swept scene's table, chart and recording and feature costs, the tuning grid and the stress
/// table (the stress suite's recordings of unstable runs vary, and are not listed).
fn main_job_outputs(scenes: &Path, out: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for path in scene_files(scenes)? {
        let scene = load_scene(&path, None, &Overrides::default())?;
        for variant in variants(&scene, &Overrides::default())? {
            files.push(out.join(format!("{}.rrd", variant.name())));
        }
    }
    for name in SWEPT_SCENES {
        for ext in ["csv", "svg", "png", "rrd"] {
            files.push(out.join(format!("{name}_sweep.{ext}")));
        }
        files.push(out.join(format!("{name}_features.csv")));
    }
    for ext in ["rrd", "csv", "svg", "png"] {
        files.push(out.join(format!("tune.{ext}")));
    }
    files.extend([out.join("stress.md"), out.join("stress.csv")]);
    Ok(files)
}

fn main_job() -> anyhow::Result<()> {
    let (scenes, out) = (Path::new("scenes"), Path::new("recordings"));
    run_all(scenes, out, &Overrides::default())?;
    if stop::requested() {
        return Ok(());
    }
    let [bending, drop] = SWEPT_SCENES.map(|name| scenes.join(format!("{name}.toml")));
    let path = bending;
    // the paper's one step a frame (the reference line) beside 4 substeps, on one cost axis
    let config = crate::sweep::SweepConfig {
        substeps: vec![1, 4],
        ..Default::default()
    };
    sweep(&path, &config, None, Shard::ALL, out)?;
    if stop::requested() {
        return Ok(());
    }
    // the drop: the paper's method (one step a frame, cheap joints, the scalar solver, hard
    // contacts) as the reference line, beside 4 substeps and contact stacking, over the fall,
    // the landing and the first seconds of the pile
    let config = crate::sweep::SweepConfig {
        iterations: vec![2, 5, 20],
        spines: vec![SpineKind::Chain3, SpineKind::Rod],
        joints: vec![JointFlavour::Cheap],
        substeps: vec![1, 4],
        solvers: vec![SolverKind::Scalar],
        contact_stacking: vec![0.0, 10.0],
        frames: Some(300),
        repeats: 1,
        ..Default::default()
    };
    sweep(&drop, &config, None, Shard::ALL, out)?;
    if stop::requested() {
        return Ok(());
    }
    // the default tuning grid of passive bending's rod spine
    let scene = Scene::load(&path)?;
    tune::run_grid(&scene, &crate::tune::TuneConfig::default(), out)?;
    stress(out)
}

/// `rodlab stress`: the suite, its table printed and saved, failing runs' recordings kept.
fn stress(out: &Path) -> anyhow::Result<()> {
    use crate::stress::{self, Method, Verdict};
    let folder = out.join("stress");
    std::fs::create_dir_all(&folder)
        .with_context(|| format!("cannot create {}", folder.display()))?;
    let cases = stress::suite();
    let started = std::time::Instant::now();
    let mut outcomes = Vec::new();
    let mut kept = Vec::new();
    let mut progress = Progress::new(cases.len() * Method::ALL.len());
    for case in &cases {
        for method in Method::ALL {
            progress.show(&format!("{} {method}", case.name));
            let name = format!("{}_{method}", case.name);
            let path = folder.join(format!("{name}.rrd"));
            // every run is recorded; a stable run's file is deleted afterwards
            let text = format!("name = \"stress_{name}\"\n# {}\n", case.description);
            let scene = Scene::parse(format!("stress/{name}"), &text)?;
            let mut recorder = LazyRecorder {
                path: path.clone(),
                scene,
                recorder: None,
            };
            let outcome = stress::run_case(case, method, &mut recorder)?;
            drop(recorder);
            match outcome {
                Some(outcome) if outcome.verdict != Verdict::Stable => {
                    kept.push(path);
                    outcomes.push(outcome);
                }
                Some(outcome) => {
                    std::fs::remove_file(&path).ok();
                    outcomes.push(outcome);
                }
                None => {
                    std::fs::remove_file(&path).ok();
                }
            }
        }
    }
    progress.finish();
    let markdown = stress::table_markdown(&outcomes);
    println!(
        "== stress: {} runs in {:.1} s",
        outcomes.len(),
        started.elapsed().as_secs_f32()
    );
    println!("{markdown}");
    let md_path = out.join("stress.md");
    let csv_path = out.join("stress.csv");
    let machine = crate::sweep::machine_name();
    std::fs::write(
        &md_path,
        format!("# rodlab stress suite\n\nMachine: {machine}. Criteria: README, section \"Where methods fail\".\n\n{markdown}"),
    )
    .with_context(|| format!("cannot write {}", md_path.display()))?;
    std::fs::write(&csv_path, stress::table_csv(&outcomes))
        .with_context(|| format!("cannot write {}", csv_path.display()))?;
    println!(
        "  -> {}, {}, and {} recordings of the runs that are not stable in {}",
        md_path.display(),
        csv_path.display(),
        kept.len(),
        folder.display()
    );
    Ok(())
}

/// Opens its recording when the run begins, since the stress cases build their own worlds.
struct LazyRecorder {
    path: PathBuf,
    scene: Scene,
    recorder: Option<Recorder>,
}

impl Observer for LazyRecorder {
    fn begin(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        let rec = record::save_to(&self.path, &self.scene)?;
        let recorder = self.recorder.insert(Recorder::new(rec, lab, &self.scene)?);
        recorder.begin(lab, metrics)
    }

    fn frame(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        match &mut self.recorder {
            Some(recorder) => recorder.frame(lab, metrics),
            None => Ok(()),
        }
    }

    fn failed(&mut self, lab: &Lab, error: &SimulationError) {
        if let Some(recorder) = &mut self.recorder {
            recorder.failed(lab, error);
        }
    }
}

/// `rodlab sweep`: every combination, with a progress bar, into CSV, SVG and a recording.
fn sweep(
    path: &Path,
    config: &crate::sweep::SweepConfig,
    peer: Option<&str>,
    shard: Shard,
    out: &Path,
) -> anyhow::Result<Vec<crate::sweep::SweepRow>> {
    use crate::sweep;
    match peer {
        None => {}
        Some("rapier") if cfg!(feature = "rapier") => {}
        Some("rapier") => anyhow::bail!(
            "--peer rapier: this rodlab was built without the Rapier peer; run \
             `cargo run --release --features rapier -- sweep ...`"
        ),
        Some(other) => anyhow::bail!("--peer {other}: unknown peer engine (known: rapier)"),
    }
    let scene = Scene::load(path)?;
    let name = scene.name();
    let all = sweep::combinations(&scene.def, config);
    let first_peer = all.len();
    let combinations: Vec<Overrides> = (all.into_iter().enumerate())
        .filter(|(i, _)| shard.takes(*i))
        .map(|(_, o)| o)
        .collect();
    let machine = sweep::machine_name();
    let peer_runs = if peer.is_some() {
        let count = config.iterations.len() * config.dts.len().max(1);
        (first_peer..first_peer + count)
            .filter(|&i| shard.takes(i))
            .count()
    } else {
        0
    };
    let runs = combinations.len() + peer_runs;
    let of = if shard == Shard::ALL {
        String::new()
    } else {
        format!(" (shard {}/{})", shard.index, shard.count)
    };
    println!("== sweep {name}: {runs} runs on {machine}{of}");
    let mut progress = Progress::new(runs);
    let mut rows = Vec::with_capacity(combinations.len());
    for overrides in &combinations {
        progress.show(&format!(
            "{}/{} {} dt={:.4} substeps={} warm={} soft={}Hz stack={} iterations={}",
            overrides.spine.unwrap_or_default(),
            overrides.joint_flavour.unwrap_or_default(),
            overrides.solver.unwrap_or(scene.def.solver),
            overrides.dt.unwrap_or(scene.def.dt),
            overrides.substeps.unwrap_or(scene.def.substeps),
            (overrides.contact_warm_start).unwrap_or(scene.def.contact_warm_start),
            (overrides.contact_hertz).unwrap_or(scene.def.contact_hertz),
            (overrides.contact_stacking).unwrap_or(scene.def.contact_stacking),
            overrides.iterations.unwrap_or(scene.def.iterations)
        ));
        rows.push(sweep::run_one(&scene, overrides, config.repeats)?);
    }
    if peer.is_some() {
        rows.extend(peer_rows(
            &scene,
            config,
            (first_peer, shard),
            &mut progress,
        )?);
    }
    progress.finish();
    println!(
        "  {:<36} {:>8} {:>4} {:>5} {:>10} {:>12} {:>12} {:>10} {:>10}",
        "method",
        "dt",
        "sub",
        "iter",
        "step us",
        "mean disl cm",
        "max disl cm",
        "mean rad",
        "overlap cm"
    );
    for r in &rows {
        match &r.failed {
            None => println!(
                "  {:<36} {:>8.4} {:>4} {:>5} {:>10.1} {:>12.4} {:>12.4} {:>10.5} {:>10.2}",
                r.method,
                r.dt,
                r.substeps,
                r.iterations,
                r.step_us,
                r.mean_dislocation_cm,
                r.max_dislocation_cm,
                r.mean_angular_rad,
                r.max_overlap_cm
            ),
            Some(e) => println!(
                "  {:<36} {:>8.4} {:>4} {:>5} failed: {e}",
                r.method, r.dt, r.substeps, r.iterations
            ),
        }
    }
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let stem = format!("{name}_sweep{}", shard.suffix());
    let csv = out.join(format!("{stem}.csv"));
    std::fs::write(&csv, sweep::to_csv(&rows))
        .with_context(|| format!("cannot write {}", csv.display()))?;
    let svg = out.join(format!("{stem}.svg"));
    let chart = sweep::chart(&name, &rows, &machine);
    std::fs::write(&svg, chart.to_svg())
        .with_context(|| format!("cannot write {}", svg.display()))?;
    let png = out.join(format!("{stem}.png"));
    let png_bytes = chart.to_png()?;
    std::fs::write(&png, &png_bytes).with_context(|| format!("cannot write {}", png.display()))?;
    let rrd = out.join(format!("{stem}.rrd"));
    record::save_sweep(&rrd, &name, &rows, &machine, &png_bytes)?;
    println!(
        "  -> {}, {} (and .png), {}",
        csv.display(),
        svg.display(),
        rrd.display()
    );
    if shard.index == 1 {
        feature_costs(&scene, out)?;
    } else {
        println!("  (the feature costs are measured by shard 1)");
    }
    Ok(rows)
}

/// The peer's rows: the scene with chain3 spines (Rapier has no rod), per time step and
/// iteration count (Rapier's `num_solver_iterations`).
#[cfg(feature = "rapier")]
fn peer_rows(
    scene: &Scene,
    config: &crate::sweep::SweepConfig,
    (first_index, shard): (usize, Shard),
    progress: &mut Progress,
) -> anyhow::Result<Vec<crate::sweep::SweepRow>> {
    let mut index = first_index;
    let dts = if config.dts.is_empty() {
        vec![scene.def.dt]
    } else {
        config.dts.clone()
    };
    let mut rows = Vec::new();
    for dt in dts {
        for &iterations in &config.iterations {
            index += 1;
            if !shard.takes(index - 1) {
                continue;
            }
            progress.show(&format!("rapier dt={dt:.4} iterations={iterations}"));
            let mut peer_scene = scene.clone();
            Overrides {
                spine: Some(SpineKind::Chain3),
                dt: Some(dt),
                frames: config.frames,
                ..Default::default()
            }
            .apply(&mut peer_scene.def);
            let mut row = crate::peer::run(&peer_scene, iterations, config.repeats)?;
            row.method = format!("{}/{}", row.method, row.spine);
            rows.push(row);
        }
    }
    Ok(rows)
}

#[cfg(not(feature = "rapier"))]
fn peer_rows(
    _: &Scene,
    _: &crate::sweep::SweepConfig,
    _: (usize, Shard),
    _: &mut Progress,
) -> anyhow::Result<Vec<crate::sweep::SweepRow>> {
    anyhow::bail!("--peer rapier: built without the feature `rapier`")
}

/// What each modelled feature costs the scene, recording included -> <scene>_features.csv.
fn feature_costs(scene: &Scene, out: &Path) -> anyhow::Result<()> {
    let frames = scene.def.frames.min(300);
    let mut costs = crate::sweep::feature_costs(scene, frames)?;
    // recording: a whole run recorded against the same run (measured and printed alike, the
    // file opened, its static data written and closed) that records no frame
    let mut short = scene.clone();
    short.def.frames = frames;
    let scratch = std::env::temp_dir().join(format!("rodlab_cost_{}.rrd", scene.name()));
    let time_run = |from: f32| -> anyhow::Result<f64> {
        let started = std::time::Instant::now();
        record_scene_from(&short, record::save_to(&scratch, &short)?, from)?;
        Ok(started.elapsed().as_secs_f64() * 1e6 / frames as f64)
    };
    let headless = time_run(f32::INFINITY)?;
    let recorded = time_run(0.0)?;
    std::fs::remove_file(&scratch).ok();
    costs.push(crate::sweep::FeatureCost {
        feature: "recording (whole frame)",
        modelled: true,
        with_us: recorded,
        without_us: headless,
    });
    println!("  what the scene pays for (median us per frame over {frames} frames):");
    println!(
        "  {:<26} {:>9} {:>10} {:>10} {:>8}",
        "feature", "modelled", "with", "without", "cost"
    );
    for c in &costs {
        println!(
            "  {:<26} {:>9} {:>10.1} {:>10.1} {:>+7.0}%",
            c.feature,
            if c.modelled { "yes" } else { "no" },
            c.with_us,
            c.without_us,
            100.0 * (c.with_us / c.without_us - 1.0)
        );
    }
    let csv = crate::csv_table::to_text(
        "feature,modelled,with_us,without_us",
        costs.iter().map(|c| {
            vec![
                c.feature.to_string(),
                c.modelled.to_string(),
                format!("{:.3}", c.with_us),
                format!("{:.3}", c.without_us),
            ]
        }),
    );
    let path = out.join(format!("{}_features.csv", scene.name()));
    std::fs::write(&path, csv).with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}

/// A one-line progress bar on a terminal; one line per run otherwise (CI logs).
struct Progress {
    total: usize,
    done: usize,
    terminal: bool,
    started: std::time::Instant,
}

impl Progress {
    fn new(total: usize) -> Self {
        use std::io::IsTerminal as _;
        Progress {
            total,
            done: 0,
            terminal: std::io::stderr().is_terminal(),
            started: std::time::Instant::now(),
        }
    }

    fn show(&mut self, label: &str) {
        const WIDTH: usize = 30;
        let filled = WIDTH * self.done / self.total.max(1);
        let bar = format!("[{}{}]", "#".repeat(filled), "-".repeat(WIDTH - filled));
        let line = format!(
            "{bar} {}/{} {:>5.1} s  {label}",
            self.done + 1,
            self.total,
            self.started.elapsed().as_secs_f32()
        );
        if self.terminal {
            eprint!("\r\x1b[2K{line}");
        } else {
            eprintln!("{line}");
        }
        self.done += 1;
    }

    fn finish(&self) {
        if self.terminal {
            eprintln!();
        }
        eprintln!(
            "  {} runs in {:.1} s",
            self.total,
            self.started.elapsed().as_secs_f32()
        );
    }
}

/// Whether the user chose where the recording goes (otherwise we save to recordings/).
fn rerun_sink_given(matches: &ArgMatches) -> bool {
    ["save", "spawn", "connect", "stdout"]
        .iter()
        .any(|id| matches!(matches.value_source(id), Some(ValueSource::CommandLine)))
}

/// A run that failed because its recording could not be written names the file and, probed
/// with a small write beside it, the OS error (a full disk: "No space left on device").
fn explain_write_failure(out: Option<&Path>, e: anyhow::Error) -> anyhow::Error {
    let Some(out) = out.filter(|_| format!("{e:#}").contains("could not be written")) else {
        return e;
    };
    let dir = out
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let probe = dir.join(format!(".rodlab-write-probe-{}", std::process::id()));
    let os_error = match std::fs::write(&probe, [0u8; 65536]) {
        Ok(()) => "a probe write beside it succeeded".to_string(),
        Err(io) => io.to_string(),
    };
    let _ = std::fs::remove_file(&probe);
    e.context(format!("writing {}: {os_error}", out.display()))
}

/// Refuses to write a recording over the scene file being run, or (unless `force`) over an
/// existing file that is not an `.rrd`.
fn check_output(out: &Path, scene: &Path, force: bool) -> anyhow::Result<()> {
    let same = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if same(out, scene) {
        anyhow::bail!(
            "--save {}: that is the scene being run; choose another file",
            out.display()
        );
    }
    let is_rrd = out.extension().is_some_and(|e| e == "rrd");
    if out.exists() && !is_rrd && !force {
        anyhow::bail!(
            "--save {}: the file exists and is not an .rrd recording; pass --force to write over it",
            out.display()
        );
    }
    Ok(())
}

/// Loads a scene, at its `[[variant]]` `variant` if given, with the command line's overrides.
pub fn load_scene(
    path: &Path,
    variant: Option<&str>,
    overrides: &Overrides,
) -> anyhow::Result<Scene> {
    let mut scene = Scene::load(path)?;
    if let Some(name) = variant {
        scene = scene.variant(name)?;
    }
    overrides.apply(&mut scene.def);
    (overrides.check_applied(&scene.def))
        .map_err(|m| anyhow::anyhow!("{}: {m}", path.display()))?;
    Ok(scene)
}

/// Runs `scene` into a recording; the recording stays readable if the run fails.
pub fn record_scene(scene: &Scene, rec: rerun::RecordingStream) -> anyhow::Result<RunReport> {
    record_scene_from(scene, rec, 0.0)
}

/// [`record_scene`], logging only the frames at or after the simulated time `from` (s).
pub fn record_scene_from(
    scene: &Scene,
    rec: rerun::RecordingStream,
    from: f32,
) -> anyhow::Result<RunReport> {
    record_scene_to(scene, rec, from, false)
}

/// [`record_scene_from`]; `live` (a viewer watching) sends every frame as it comes instead of
/// a block per simulated second.
fn record_scene_to(
    scene: &Scene,
    rec: rerun::RecordingStream,
    from: f32,
    live: bool,
) -> anyhow::Result<RunReport> {
    if scene.def.kinematics.is_some() {
        let (equal, unequal) = record::record_kinematics(&rec, scene)?;
        report!(
            "  largest end gap from the rod: equal-angle chain {:.2} cm, unequal-angle chain {:.2} cm",
            100.0 * equal,
            100.0 * unequal
        );
        return Ok(RunReport {
            frames: scene.def.frames,
            ragdolls: Vec::new(),
            initial_energy: 0.0,
            final_energy: 0.0,
            final_rods: Vec::new(),
            total_dislocation_cm: Vec::new(),
            max_penetration_cm: 0.0,
            max_overlap_cm: 0.0,
            step_seconds: 0.0,
            awake_bodies: Vec::new(),
            profile: Default::default(),
            restless: Vec::new(),
            state_hash: 0,
        });
    }
    let mut lab = scene.build()?;
    let mut recorder = Recorder::new(rec, &lab, scene)?;
    recorder.live = live;
    let mut late = FromTime {
        inner: &mut recorder,
        from: from as f64 - 0.5 * scene.def.dt as f64,
    };
    let mut observer = RowPrinter {
        inner: &mut late,
        every: scene.def.report_every,
    };
    let report = sim::run(&mut lab, scene.def.frames, &mut observer)
        .with_context(|| format!("{}: simulation stopped", scene.path.display()))?;
    recorder.finish(&report)?;
    Ok(report)
}

/// Hands on the frames at or after the simulated time `from` (s) only; a failure always.
struct FromTime<'a> {
    inner: &'a mut dyn Observer,
    from: f64,
}

impl Observer for FromTime<'_> {
    fn begin(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        match lab.world.time >= self.from {
            true => self.inner.begin(lab, metrics),
            false => Ok(()),
        }
    }

    fn frame(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        match lab.world.time >= self.from {
            true => self.inner.frame(lab, metrics),
            false => Ok(()),
        }
    }

    fn failed(&mut self, lab: &Lab, error: &SimulationError) {
        self.inner.failed(lab, error);
    }
}

/// Prints one row of residuals per ragdoll every `every` frames, then hands on the frame.
struct RowPrinter<'a> {
    inner: &'a mut dyn Observer,
    every: u32,
}

impl Observer for RowPrinter<'_> {
    fn begin(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        if self.every > 0 {
            report!(
                "  {:>6} {:>8} {:<14} {:>10} {:>10} {:>14}",
                "frame",
                "time s",
                "ragdoll",
                "disl. cm",
                "ang. rad",
                "pose dev. cm"
            );
        }
        self.inner.begin(lab, metrics)
    }

    fn stop_requested(&self) -> bool {
        stop::requested()
    }

    fn frame(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        if self.every > 0 && lab.world.frame % self.every as u64 == 0 {
            for (ragdoll, r) in lab.ragdolls.iter().zip(&metrics.ragdolls) {
                report!(
                    "  {:>6} {:>8.3} {:<14} {:>10.4} {:>10.5} {:>14.4}",
                    lab.world.frame,
                    lab.world.time,
                    ragdoll.name,
                    r.dislocation_cm,
                    r.angular_rad,
                    r.pose_deviation_cm
                );
            }
        }
        self.inner.frame(lab, metrics)
    }

    fn failed(&mut self, lab: &Lab, error: &SimulationError) {
        self.inner.failed(lab, error)
    }
}

fn run_one(
    scene: &Scene,
    record_from: f32,
    rerun_args: &rerun::clap::RerunArgs,
    sink_given: bool,
    save_path: Option<&Path>,
) -> anyhow::Result<()> {
    let name = scene.name();
    let (rec, _serve_guard, out) = if let Some(path) = save_path {
        // ours rather than `RerunArgs`' file sink: the same writer as the main job's
        (
            record::save_to(path, scene)?,
            Default::default(),
            Some(path.to_path_buf()),
        )
    } else if sink_given {
        let (rec, guard) =
            rerun_args.init_with_blueprint(record::APPLICATION_ID, record::blueprint(scene))?;
        (rec, guard, None)
    } else {
        let out = Path::new("recordings").join(format!("{name}.rrd"));
        eprintln!("recording to {}", out.display());
        (record::save_to(&out, scene)?, Default::default(), Some(out))
    };
    // no file: a viewer (--spawn, --connect) or a pipe, sent frame by frame
    let report = record_scene_to(scene, rec, record_from, out.is_none())
        .map_err(|e| explain_write_failure(out.as_deref(), e))?;
    print_summary(&name, scene, &report);
    if stop::requested() {
        report!(
            "  stopped by {} after {} of {} frames",
            stop::signal_name(),
            report.frames,
            scene.def.frames
        );
    }
    Ok(())
}

/// The scene files (`*.toml`) in `dir`, sorted.
fn scene_files(dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("cannot list scenes in {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    paths.sort();
    anyhow::ensure!(
        !paths.is_empty(),
        "no scene files (*.toml) in {}",
        dir.display()
    );
    Ok(paths)
}

fn run_all(scenes_dir: &Path, out_dir: &Path, overrides: &Overrides) -> anyhow::Result<()> {
    let paths = scene_files(scenes_dir)?;
    let mut failures = Vec::new();
    for path in &paths {
        if stop::requested() {
            break;
        }
        let result = load_scene(path, None, overrides).and_then(|mut scene| {
            // heavy scenes give the main job a shorter run (`ci_frames`), unless --frames
            if let (None, Some(n)) = (overrides.frames, scene.def.ci_frames) {
                println!(
                    "{}: main job runs {n} of its {} frames (ci_frames; `rodlab run` runs all)",
                    scene.name(),
                    scene.def.frames
                );
                scene.def.frames = n;
            }
            let mut reports = Vec::new();
            for variant in variants(&scene, overrides)? {
                if stop::requested() {
                    break;
                }
                let name = variant.name();
                let out = out_dir.join(format!("{name}.rrd"));
                let started = std::time::Instant::now();
                let report = record_scene(&variant, record::save_to(&out, &variant)?)
                    .map_err(|e| explain_write_failure(Some(&out), e))?;
                print_summary(&name, &variant, &report);
                println!(
                    "  -> {} ({:.1} s)",
                    out.display(),
                    started.elapsed().as_secs_f32()
                );
                reports.push((name, report));
            }
            // two spines: compare them, per method
            if scene.def.spines.len() == 2 && overrides.spine.is_none() {
                for pair in reports.chunks_exact(2) {
                    let [(name_a, a), (name_b, b)] = pair else {
                        unreachable!()
                    };
                    print_comparison(name_a, a, name_b, b);
                }
            }
            Ok(())
        });
        if let Err(e) = result {
            eprintln!("error: {e:#}");
            failures.push(path.display().to_string());
        }
    }
    anyhow::ensure!(
        failures.is_empty(),
        "{} scene(s) failed: {}",
        failures.len(),
        failures.join(", ")
    );
    Ok(())
}

/// The runs the main job makes of a scene: the scene's own method, then each `[[variant]]`
/// (named `<scene>_<variant>`, the command line's overrides applied again on top); each once
/// per spine listed in `spines` (named `<name>_<spine>`), unless the command line fixed the
/// spine.
fn variants(scene: &Scene, overrides: &Overrides) -> anyhow::Result<Vec<Scene>> {
    let mut methods = vec![scene.clone()];
    for variant in &scene.def.variant {
        let mut method = scene.variant(&variant.name)?;
        overrides.apply(&mut method.def);
        methods.push(method);
    }
    if scene.def.spines.is_empty() || overrides.spine.is_some() {
        return Ok(methods);
    }
    let mut runs = Vec::new();
    for method in &methods {
        for &spine in &method.def.spines {
            let mut run = method.clone();
            Overrides {
                spine: Some(spine),
                ..Default::default()
            }
            .apply(&mut run.def);
            run.def.name = Some(format!("{}_{spine}", method.name()));
            runs.push(run);
        }
    }
    Ok(runs)
}

/// Mean total dislocation of two runs of one scene, and the share of frames where the second
/// leaves less than the first (the paper's Fig. 8 comparison).
fn print_comparison(name_a: &str, a: &RunReport, name_b: &str, b: &RunReport) {
    let mean = |r: &RunReport| {
        r.total_dislocation_cm.iter().sum::<f32>() / r.total_dislocation_cm.len().max(1) as f32
    };
    let frames = a
        .total_dislocation_cm
        .len()
        .min(b.total_dislocation_cm.len());
    let better = (0..frames)
        .filter(|&i| b.total_dislocation_cm[i] < a.total_dislocation_cm[i])
        .count();
    println!(
        "  total dislocation, mean over frames: {name_a} {:.3} cm, {name_b} {:.3} cm; {name_b} below {name_a} in {:.1}% of frames",
        mean(a),
        mean(b),
        100.0 * better as f32 / frames.max(1) as f32
    );
}

fn check(paths: &[PathBuf]) -> anyhow::Result<()> {
    for path in paths {
        let scene = Scene::load(path)?;
        let lab = scene.build()?;
        println!(
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

pub fn print_summary(name: &str, scene: &Scene, report: &RunReport) {
    if scene.def.kinematics.is_some() {
        report!("{name}: {} bends recorded", report.frames);
        return;
    }
    report!(
        "{name}: {} frames, dt {:.4} s, {} substep(s) x {} iterations, {} solver on {} thread(s), \
         {:.0} steps/s (stepping only), energy {:.1} J -> {:.1} J, state hash {:016x}",
        report.frames,
        scene.def.dt,
        scene.def.substeps,
        scene.def.iterations,
        scene.def.solver,
        rayon::current_num_threads(),
        report.steps_per_second(),
        report.initial_energy,
        report.final_energy,
        report.state_hash
    );
    if report.ragdolls.len() > 4 {
        let frames = report.total_dislocation_cm.len().max(1) as f32;
        let mean = report.total_dislocation_cm.iter().sum::<f32>() / frames;
        let angular: f64 = report
            .ragdolls
            .iter()
            .map(|r| r.summary.mean_angular_rad())
            .sum();
        report!(
            "  {} ragdolls: total dislocation {mean:.3} cm and angular violation {angular:.4} rad, means over frames",
            report.ragdolls.len()
        );
        print_penetration(report);
        print_sleep(scene, report);
        print_profile(report);
        return;
    }
    report!(
        "  {:<14} {:<7} {:>14} {:>13} {:>15} {:>14} {:>18}",
        "ragdoll",
        "spine",
        "mean disl. cm",
        "max disl. cm",
        "mean ang. rad",
        "max ang. rad",
        "mean pose dev. cm"
    );
    for r in &report.ragdolls {
        report!(
            "  {:<14} {:<7} {:>14.4} {:>13.4} {:>15.5} {:>14.5} {:>18.4}",
            r.name,
            r.spine.to_string(),
            r.summary.mean_dislocation_cm(),
            r.summary.dislocation_max,
            r.summary.mean_angular_rad(),
            r.summary.angular_max,
            r.summary.mean_pose_deviation_cm()
        );
    }
    if scene.def.contacts {
        print_penetration(report);
    }
    print_sleep(scene, report);
    print_profile(report);
    for (i, rod) in report.final_rods.iter().enumerate() {
        report!(
            "  rod {i}: final psi {:.3} rad, tau {:.3} rad, length violation {:.4} cm, curve violation {:.5} rad",
            rod.psi,
            rod.tau,
            100.0 * rod.length_error,
            rod.curve_error
        );
    }
}

/// The step's phases, mean per frame (ms), the ones that took any time.
fn print_profile(report: &RunReport) {
    let frames = report.total_dislocation_cm.len().max(1) as f64; // frames stepped
    let phases: Vec<String> = (report.profile.phases().iter())
        .filter(|(_, s)| *s > 0.0)
        .map(|(name, s)| format!("{name} {:.3}", 1e3 * s / frames))
        .collect();
    if !phases.is_empty() {
        report!("  step profile, ms per frame: {}", phases.join(", "));
    }
}

/// The deepest penetration at the solver's contact points and the deepest overlap found afresh
/// on the final poses, over the run: the second catches what the first misses when bodies
/// slide over each other within a frame.
fn print_penetration(report: &RunReport) {
    report!(
        "  deepest contact penetration: {:.3} cm at the contact points, {:.3} cm found afresh",
        report.max_penetration_cm,
        report.max_overlap_cm
    );
}

/// With sleeping on: the awake bodies at the end, and the first frame with none awake.
fn print_sleep(scene: &Scene, report: &RunReport) {
    if !scene.def.sleep {
        return;
    }
    let last = report.awake_bodies.last().copied().unwrap_or(0);
    let all_asleep = report.awake_bodies.iter().position(|&n| n == 0);
    report!(
        "  sleeping: {last} dynamic bodies awake at the end{}",
        all_asleep.map_or(String::new(), |f| format!(
            "; all asleep from frame {}",
            f + 1
        ))
    );
    print_restless(report);
}

/// The bodies that keep their islands awake at the end, fastest first (at most five named).
fn print_restless(report: &RunReport) {
    const NAMED: usize = 5;
    let Some((name, fastest)) = report.restless.first() else {
        return;
    };
    report!(
        "  still moving (fastest surface point >= {} m/s): {} bodies; fastest {name} {:.3} m/s",
        crate::sleep::SLEEP_SPEED,
        report.restless.len(),
        fastest.point_speed
    );
    for (name, r) in report.restless.iter().take(NAMED) {
        report!(
            "    {name}: point {:.3} m/s, centre {:.3} m/s, spin {:.2} rad/s about its axis and {:.2} across",
            r.point_speed, r.centre_speed, r.axial_spin, r.cross_spin
        );
    }
}
