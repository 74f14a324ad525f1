//! The command line's arguments (clap derive) and their value parsers.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

use crate::constraint::{BendTwist, JointFlavour, TwistMode};
use crate::ragdoll::{SelfContacts, SpineKind};
use crate::scene::bounds::MAX_THREADS;
use crate::scene::{Method, RodOverrides, SoftnessOverride};
use crate::sim::Overrides;

use super::parse::{
    non_negative, parse_choice, positive_stiffness, seed_list, unit_interval, SeedList,
};
use super::settings_args::{set_method_setting, MethodFlags, MethodListFlags};
use super::tune;

/// The `rodlab` command line.
#[derive(Debug, Parser)]
#[command(
    name = "rodlab",
    version,
    about = "Rod constraints for simplified ragdolls (SCA 2013), recorded to Rerun"
)]
pub struct Cli {
    /// The command to run; without one, the main job.
    #[command(subcommand)]
    pub command: Option<Command>,
}

// The doc comments are `--help` text, where `<out>` is a placeholder, not HTML.
/// The subcommands of `rodlab`.
// A command is parsed once per process, so its variants' sizes do not matter.
#[allow(rustdoc::invalid_html_tags, clippy::large_enum_variant)]
#[derive(Debug, Subcommand)]
pub enum Command {
    /// The main job: every scene in a folder -> <out>/<scene>.rrd, plus a residual summary
    /// (a scene with `ci_frames` runs that many frames, unless --frames).
    #[command(
        after_help = "Example: rodlab all --out recordings   (the main job, as `cargo run --release` runs it)"
    )]
    All {
        /// Folder of scene files (*.toml) to run
        #[arg(long, default_value = "scenes")]
        scenes: PathBuf,
        /// Folder the recordings are written to
        #[arg(long, default_value = "recordings")]
        out: PathBuf,
        /// Settings that override every scene's.
        #[command(flatten)]
        overrides: OverrideArgs,
    },
    /// Runs one scene and records it.
    #[command(
        after_help = "Example: rodlab run scenes/ragdoll_drop.toml --method game --spine rod --set contact_hertz=60 --save drop.rrd",
        mut_arg("server_memory_limit", |a| a.hide(true)),
        mut_arg("newest_first", |a| a.hide(true)),
        mut_arg("bind", |a| a.hide(true))
    )]
    Run {
        /// Scene file (TOML) to run
        scene: PathBuf,
        /// Run the scene's `[[variant]]` of this name (its settings, then the overrides below),
        /// recorded as <scene>_<variant>.
        #[arg(long)]
        variant: Option<String>,
        /// Record only the frames from this simulated time on (s; the run still starts at 0):
        /// a smaller file of how a long run ends.
        #[arg(long, value_parser = non_negative, default_value_t = 0.0)]
        record_from: f32,
        /// Let --save write over an existing path that is not a recording of its own: a symbolic
        /// link, a file with other hard links, or a file without Rerun's header (never the scene).
        #[arg(long)]
        force: bool,
        /// Settings that override the scene's.
        #[command(flatten)]
        overrides: OverrideArgs,
        /// Where the recording goes (Rerun's `--save`, `--spawn`, `--connect`, ...).
        #[command(flatten)]
        rerun: rerun::clap::RerunArgs,
    },
    /// Speed against accuracy: runs SCENE headless for every spine, joint flavour, time step
    /// and iteration count -> <out>/<scene>_sweep.csv, .svg (chart) and .rrd, and with contacts
    /// <out>/<scene>_sweep_overlap.svg (the deepest overlap against time).
    #[command(
        after_help = "Example: rodlab sweep scenes/passive_bending.toml --spines chain3,rod --iterations 1,2,4,8,16,32"
    )]
    Sweep(SweepArgs),
    /// Tuning by eye: every combination of bend and twist settings (and iteration counts) as
    /// one copy of the scene's rod-spine ragdoll on a labelled grid -> <out>/tune.rrd, .csv,
    /// .svg, .png; or, with --match-psi / --match, the settings that settle at a bend.
    #[command(
        after_help = "Example: rodlab tune scenes/passive_bending.toml --alpha-b 0,0.005,0.02 --alpha-t 0,0.5"
    )]
    Tune(tune::TuneArgs),
    /// The stability suite: every case for every method, a verdict each -> <out>/stress.md,
    /// <out>/stress.csv, and a recording of every run that is not stable (<out>/stress/).
    #[command(after_help = "Example: rodlab stress --out recordings")]
    Stress {
        /// Folder for stress.md, stress.csv and the recordings of runs that are not stable
        #[arg(long, default_value = "recordings")]
        out: PathBuf,
    },
    /// Robustness over layouts: runs a scene with a `[drop]` block headless once per layout
    /// seed and spine -> <out>/<scene>_layouts.md and .csv (<scene>_<variant>_layouts with
    /// --variant): whether each run ended at rest, its deepest overlap, or where it stopped.
    #[command(
        after_help = "Example: rodlab layouts scenes/ragdoll_drop.toml --variant game --seeds 1-128"
    )]
    Layouts(LayoutsArgs),
    /// Validates scene files without running them.
    #[command(after_help = "Example: rodlab check scenes/*.toml")]
    Check {
        /// Scene files (TOML) to check
        #[arg(required = true)]
        scenes: Vec<PathBuf>,
    },
    /// Lists the files the main job writes, one per line (what CI checks and archives).
    #[command(after_help = "Example: rodlab outputs")]
    Outputs,
    /// The named methods (paper, game, tight): each one's settings, as a scene file writes them.
    #[command(after_help = "Example: rodlab methods")]
    Methods,
    /// The method settings: each one's key (a scene file's, a `[[variant]]`'s; the flag is the
    /// key with dashes), unit, values, value in each named method and what it does.
    #[command(after_help = "Example: rodlab settings")]
    Settings,
    /// The criterion benchmarks' last results (`cargo bench` first) as data ->
    /// <out>/<machine>/criterion.csv: each benchmark's median time, its 95% interval and the time
    /// per element, the machine named as the CPU reports it.
    #[command(
        after_help = "Example: rodlab benchmarks --out docs/benchmarks   (after `cargo bench`)"
    )]
    Benchmarks {
        /// criterion's output folder
        #[arg(long, default_value = "target/criterion")]
        criterion: PathBuf,
        /// Folder the machine's folder is written under
        #[arg(long, default_value = "docs/benchmarks")]
        out: PathBuf,
    },
    /// A sweep's shards (`sweep --shard I/N`) back into the whole sweep: every shard's
    /// <name>_sweep_shardIofN.csv -> <out>/<name>_sweep.csv, .svg, .png and .rrd, in the order an
    /// unsharded run writes them.
    #[command(
        after_help = "Example: rodlab merge recordings/passive_bending_sweep_shard*of3.csv --out recordings"
    )]
    Merge {
        /// The shards' CSV files, all N of one sweep, in any order
        #[arg(required = true)]
        shards: Vec<PathBuf>,
        /// Folder for the merged table, chart and recording
        #[arg(long, default_value = "recordings")]
        out: PathBuf,
        /// The machine the shards ran on, for the chart's title (the CSVs do not say)
        #[arg(long, default_value = "machine not named")]
        machine: String,
    },
}

/// The arguments of `rodlab layouts`.
#[derive(Debug, Clone, Args)]
pub struct LayoutsArgs {
    /// Scene file (TOML) with a `[drop]` block
    pub scene: PathBuf,
    /// Run the scene's `[[variant]]` of this name (its settings, then the overrides below).
    #[arg(long)]
    pub variant: Option<String>,
    /// Layout seeds: numbers and ranges, comma separated (e.g. 1-16,20).
    #[arg(long, default_value = "1-8", value_parser = seed_list)]
    pub seeds: SeedList,
    /// Spines, comma separated; default the scene's `spines`, else chain3,rod (rig,rod for
    /// game characters).
    #[arg(long, value_delimiter = ',', value_parser = parse_choice::<SpineKind>)]
    pub spines: Vec<SpineKind>,
    /// A run whose deepest overlap passes this (cm) is counted in the summary.
    #[arg(long, value_parser = non_negative, default_value_t = 1.0)]
    pub overlap_cm: f32,
    /// Folder for the table and the CSV.
    #[arg(long, default_value = "recordings")]
    pub out: PathBuf,
    /// Settings that override the scene's (not --seed or --spine: the layouts set those).
    #[command(flatten)]
    pub overrides: OverrideArgs,
}

/// The arguments of `rodlab sweep`.
#[derive(Debug, Clone, Args)]
pub struct SweepArgs {
    /// Scene file (TOML) to sweep
    pub scene: PathBuf,
    /// Named methods, comma separated (paper, game, tight): one line each, the other lists
    /// left unset keeping each method's settings.
    #[arg(long, value_delimiter = ',', value_parser = parse_choice::<Method>)]
    pub methods: Vec<Method>,
    /// Spines, comma separated; default the scene's `spines` and single, else chain3,rod,single
    /// (rig,rod,single for game characters).
    #[arg(long, value_delimiter = ',', value_parser = parse_choice::<SpineKind>)]
    pub spines: Vec<SpineKind>,
    /// Joint flavours, comma separated; default cheap,exact (with --methods, each method's).
    #[arg(long, value_delimiter = ',', value_parser = parse_choice::<JointFlavour>)]
    pub joint: Vec<JointFlavour>,
    /// The rod spine's parts, comma separated: sequential (the reference), block (bend and
    /// twist as one block, curve and length on shared frames); default the scene's. Other
    /// spines run once.
    #[arg(long, value_delimiter = ',', value_parser = parse_choice::<BendTwist>)]
    pub bend_twist: Vec<BendTwist>,
    /// Worker threads of the solver (at most 1024); default rayon's (one per core).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=MAX_THREADS))]
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
    /// Folder for the CSV, the chart and the recording
    #[arg(long, default_value = "recordings")]
    pub out: PathBuf,
    /// Values of the method settings, one dimension each (`--iterations`, unset, runs
    /// 1,2,4,8,16,32; with --methods it counts solves per frame, a method at S substeps running
    /// N / S iterations each, at least one).
    #[command(flatten)]
    pub settings: MethodListFlags,
}

/// Settings that override a scene file's, for `run` and `all`.
#[derive(Debug, Clone, Args)]
pub struct OverrideArgs {
    /// A named method: paper (the reference), game (at rest, asleep, gentle) or tight (low
    /// error for the paper's budget); the flags below override single fields of it
    /// (`rodlab methods` prints each).
    #[arg(long, value_parser = parse_choice::<Method>)]
    pub method: Option<Method>,
    /// Worker threads of the solver (at most 1024); default rayon's (one per core).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=MAX_THREADS))]
    pub threads: Option<u64>,
    /// Frames to simulate.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub frames: Option<u32>,
    /// Spine of every ragdoll (chain3, rod or single) and game character (rig, rod or single).
    #[arg(long, value_parser = parse_choice::<SpineKind>)]
    pub spine: Option<SpineKind>,
    /// Ball-and-socket solver: cheap or exact.
    #[arg(long, hide = true, value_parser = parse_choice::<JointFlavour>)]
    pub joint: Option<JointFlavour>,
    /// Which pairs of each ragdoll's own bodies may collide: all, apart_at_rest or none.
    #[arg(long, hide = true, value_parser = parse_choice::<SelfContacts>)]
    pub self_contacts: Option<SelfContacts>,
    /// Rod bending relaxation alpha_b in [0, 1].
    #[arg(long, value_parser = unit_interval)]
    pub alpha_b: Option<f32>,
    /// Rod twisting relaxation alpha_t in [0, 1].
    #[arg(long, value_parser = unit_interval)]
    pub alpha_t: Option<f32>,
    /// Rod bending stiffness (N m/rad), solved in compliance form instead of alpha_b: the
    /// same stiffness at any iteration count, time step or substep count.
    #[arg(long, hide = true, value_parser = positive_stiffness, conflicts_with = "alpha_b")]
    pub bend_stiffness: Option<f32>,
    /// Damping of the rod's bend rate (N m s/rad), with a bending stiffness.
    #[arg(long, hide = true, value_parser = non_negative)]
    pub bend_damping: Option<f32>,
    /// Rod twisting stiffness (N m/rad), instead of alpha_t.
    #[arg(long, hide = true, value_parser = positive_stiffness, conflicts_with = "alpha_t")]
    pub twist_stiffness: Option<f32>,
    /// Damping of the rod's twist rate (N m s/rad), with a twisting stiffness.
    #[arg(long, hide = true, value_parser = non_negative)]
    pub twist_damping: Option<f32>,
    /// Rod twist measure: exact or paper.
    #[arg(long, hide = true, value_parser = parse_choice::<TwistMode>)]
    pub twist: Option<TwistMode>,
    /// Rod parts: sequential (bend, twist, curve, length one after the other, the default) or
    /// block (bend and twist as one 2x2 block, then curve and length from the same frames).
    #[arg(long, hide = true, value_parser = parse_choice::<BendTwist>)]
    pub bend_twist: Option<BendTwist>,
    /// Record every N-th frame (frames 0, N, 2N, ...): a smaller file of a long run.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub record_every: Option<u32>,
    /// Seed of the `[drop]` block's layout (each ragdoll's random yaw and tip): another
    /// sample of the same drop.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Any other setting, as a scene file writes it: a method setting (`rodlab settings` lists
    /// them), joint_flavour, self_contacts, or every rod's bend_stiffness, bend_damping,
    /// twist_stiffness, twist_damping, twist or bend_twist; checked against the scene file's
    /// bounds; repeatable, the last one wins (e.g. --set contact_hertz=90 --set solver=simd).
    #[arg(long = "set", value_name = "KEY=VALUE", value_parser = parse_set)]
    pub set: Vec<(String, String)>,
    /// The method settings.
    #[command(flatten)]
    pub settings: MethodFlags,
}

/// One `--set KEY=VALUE`, checked as it will be applied.
fn parse_set(s: &str) -> Result<(String, String), String> {
    let (key, value) = (s.split_once('='))
        .ok_or_else(|| format!("`{s}` is not KEY=VALUE (e.g. contact_hertz=90)"))?;
    let (key, value) = (key.trim().to_string(), value.trim().to_string());
    set_setting(&mut Overrides::default(), &key, &value)?;
    Ok((key, value))
}

/// Writes the setting `key` of `overrides` from its text, checked against its bounds.
fn set_setting(o: &mut Overrides, key: &str, text: &str) -> Result<(), String> {
    if set_method_setting(o, key, text)? {
        return Ok(());
    }
    let (bend, twist) = (&mut o.rod.bend, &mut o.rod.twist);
    match key {
        "method" => o.method = Some(parse_choice(text)?),
        "joint_flavour" => o.joint_flavour = Some(parse_choice(text)?),
        "self_contacts" => o.self_contacts = Some(parse_choice(text)?),
        // an alpha and a stiffness replace each other: the last one given wins
        "alpha_b" => (bend.alpha, bend.stiffness) = (Some(unit_interval(text)?), None),
        "alpha_t" => (twist.alpha, twist.stiffness) = (Some(unit_interval(text)?), None),
        "bend_stiffness" => (bend.alpha, bend.stiffness) = (None, Some(positive_stiffness(text)?)),
        "twist_stiffness" => {
            (twist.alpha, twist.stiffness) = (None, Some(positive_stiffness(text)?))
        }
        "bend_damping" => bend.damping = Some(non_negative(text)?),
        "twist_damping" => twist.damping = Some(non_negative(text)?),
        "twist" => o.rod.twist_measure = Some(parse_choice(text)?),
        "bend_twist" => o.rod.bend_twist = Some(parse_choice(text)?),
        _ => {
            return Err(format!(
                "unknown key `{key}`: a method setting (`rodlab settings`), method, \
                 joint_flavour, self_contacts, alpha_b, alpha_t, bend_stiffness, bend_damping, \
                 twist_stiffness, twist_damping, twist or bend_twist"
            ))
        }
    }
    Ok(())
}

impl From<&OverrideArgs> for Overrides {
    fn from(a: &OverrideArgs) -> Self {
        let mut overrides = Overrides {
            method: a.method,
            self_contacts: a.self_contacts,
            seed: a.seed,
            frames: a.frames,
            spine: a.spine,
            joint_flavour: a.joint,
            rod: RodOverrides {
                bend: SoftnessOverride {
                    alpha: a.alpha_b,
                    stiffness: a.bend_stiffness,
                    damping: a.bend_damping,
                },
                twist: SoftnessOverride {
                    alpha: a.alpha_t,
                    stiffness: a.twist_stiffness,
                    damping: a.twist_damping,
                },
                twist_measure: a.twist,
                bend_twist: a.bend_twist,
            },
            name: None,
            record_every: a.record_every,
            ..Default::default()
        };
        a.settings.write_into(&mut overrides);
        for (key, value) in &a.set {
            set_setting(&mut overrides, key, value).expect("checked when parsed");
        }
        overrides
    }
}
