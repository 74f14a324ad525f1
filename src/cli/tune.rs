//! `rodlab tune`: the tuning grid into `<out>/tune.rrd`, `.csv`, `.svg` and `.png`; or, with
//! `--match-psi` / `--match`, the bend settings that settle at a wanted bend.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context as _};
use clap::Args;
use rayon::prelude::*;

use super::parse::{non_negative, parse_choice, positive_stiffness, unit_interval};
use crate::ragdoll::SpineKind;
use crate::record::tune::TuneRecorder;
use crate::scene::bounds::{MAX_FRAMES, MAX_ITERATIONS};
use crate::scene::Scene;
use crate::tune::{self, MatchBy, RodSetting, Shard, Softness, TuneConfig, TuneRow};

/// The arguments of `rodlab tune`.
#[derive(Debug, Clone, Args)]
pub struct TuneArgs {
    /// Scene whose rod-spine ragdoll is copied (its first, else its first ragdoll as rod).
    #[arg(default_value = "scenes/passive_bending.toml")]
    pub scene: PathBuf,
    /// Bend rows as alpha_b values, comma separated (default 0,0.002,0.005,0.02,0.1).
    #[arg(long, value_delimiter = ',', value_parser = unit_interval, conflicts_with = "bend_stiffness")]
    pub alpha_b: Vec<f32>,
    /// Twist columns as alpha_t values, comma separated (default 0,0.1,0.5,1).
    #[arg(long, value_delimiter = ',', value_parser = unit_interval, conflicts_with = "twist_stiffness")]
    pub alpha_t: Vec<f32>,
    /// Bend rows as stiffness (N m/rad), comma separated, instead of alpha_b.
    #[arg(long, value_delimiter = ',', value_parser = positive_stiffness)]
    pub bend_stiffness: Vec<f32>,
    /// Twist columns as stiffness (N m/rad), comma separated, instead of alpha_t.
    #[arg(long, value_delimiter = ',', value_parser = positive_stiffness)]
    pub twist_stiffness: Vec<f32>,
    /// Damping of the bend stiffness rows (N m s/rad).
    #[arg(long, value_parser = non_negative, requires = "bend_stiffness")]
    pub bend_damping: Option<f32>,
    /// Damping of the twist stiffness columns (N m s/rad).
    #[arg(long, value_parser = non_negative, requires = "twist_stiffness")]
    pub twist_damping: Option<f32>,
    /// Iteration counts, a third axis of the grid (default the scene's).
    #[arg(long, value_delimiter = ',',
          value_parser = clap::value_parser!(u32).range(1..=MAX_ITERATIONS as i64))]
    pub iterations: Vec<u32>,
    /// Frames per copy (default the scene's).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=MAX_FRAMES as i64))]
    pub frames: Option<u32>,
    /// Angular velocity (rad/s) about the rod's tangent given to the chest at the start.
    #[arg(long, default_value_t = 2.0)]
    pub twist_push: f32,
    /// Instead of the grid: bisect alpha_b and the bend stiffness until the settled psi is
    /// this angle (rad), at each iteration count.
    #[arg(long, conflicts_with = "match_spine")]
    pub match_psi: Option<f32>,
    /// Instead of the grid: match the settled slump of this spine (chain3) in the same scene.
    #[arg(long = "match", id = "match_spine", value_parser = parse_choice::<SpineKind>)]
    pub match_spine: Option<SpineKind>,
    /// Run only shard I of N of the combinations (I/N, e.g. 2/3); outputs get a _shardIofN
    /// suffix.
    #[arg(long, value_parser = |s: &str| s.parse::<Shard>())]
    pub shard: Option<Shard>,
    /// Folder for tune.rrd, .csv, .svg and .png
    #[arg(long, default_value = "recordings")]
    pub out: PathBuf,
}

impl TuneArgs {
    /// The first twist setting given on the command line, if any.
    fn given_twist(&self) -> Option<Softness> {
        (self
            .twist_stiffness
            .first()
            .map(|&k| Softness::Stiffness(k)))
        .or(self.alpha_t.first().map(|&a| Softness::Alpha(a)))
    }

    fn config(&self) -> TuneConfig {
        let default = TuneConfig::default();
        let axis = |alphas: &[f32], stiffness: &[f32], default: Vec<Softness>| {
            if !stiffness.is_empty() {
                stiffness.iter().map(|&k| Softness::Stiffness(k)).collect()
            } else if !alphas.is_empty() {
                alphas.iter().map(|&a| Softness::Alpha(a)).collect()
            } else {
                default
            }
        };
        TuneConfig {
            bend: axis(&self.alpha_b, &self.bend_stiffness, default.bend),
            twist: axis(&self.alpha_t, &self.twist_stiffness, default.twist),
            bend_damping: self.bend_damping,
            twist_damping: self.twist_damping,
            iterations: self.iterations.clone(),
            frames: self.frames,
            twist_push: self.twist_push,
            shard: self.shard.unwrap_or(Shard::ALL),
        }
    }
}

/// What the matching found at one iteration count.
#[derive(Clone, Debug, PartialEq)]
pub struct Matched {
    /// The iteration count it was matched at.
    pub iterations: u32,
    /// The settled bend angle psi sought (rad).
    pub target: f32,
    /// (alpha_b, its settled psi), if any alpha reaches the target.
    pub alpha_b: Option<(f32, f32)>,
    /// (bend stiffness N m/rad, its settled psi).
    pub bend_stiffness: Option<(f32, f32)>,
}

/// `--match-psi` / `--match`: both bend settings that settle at the target, per iteration
/// count; printed and returned.
pub fn match_bend(args: &TuneArgs, scene: &Scene) -> anyhow::Result<Vec<Matched>> {
    let config = args.config();
    let twist = args
        .given_twist()
        .map_or_else(|| tune::scene_twist(scene), Ok)?;
    let iterations = if config.iterations.is_empty() {
        vec![scene.def.iterations]
    } else {
        config.iterations.clone()
    };
    let mut found = Vec::new();
    for n in iterations {
        let target = match (args.match_psi, args.match_spine) {
            (Some(psi), _) => psi,
            (None, Some(SpineKind::Chain3)) => {
                let Some(psi) = tune::chain3_psi(scene, n)? else {
                    bail!("--match chain3: the chain3 spine does not settle in {} frames at {n} iterations", scene.def.frames);
                };
                report!("  chain3 spine at {n} iterations settles at psi {psi:.4} rad");
                psi
            }
            (None, Some(other)) => bail!("--match {other}: only chain3 can be matched"),
            (None, None) => unreachable!("match_bend needs --match-psi or --match"),
        };
        let tolerance = tune::match_tolerance(target);
        let (alpha, stiffness) = rayon::join(
            || tune::match_psi(scene, target, MatchBy::AlphaBend, twist, n, tolerance),
            || tune::match_psi(scene, target, MatchBy::BendStiffness, twist, n, tolerance),
        );
        let (alpha, stiffness) = (alpha?, stiffness?);
        let show = |found: Option<(f32, f32)>, unit: &str| match found {
            Some((v, psi)) => format!("{v:.5}{unit} (settles at {psi:.4} rad)"),
            None => "out of reach".into(),
        };
        report!(
            "  psi {target:.4} rad at {n} iterations, {}: alpha_b {}, bend_stiffness {}",
            twist.label("twist"),
            show(alpha, ""),
            show(stiffness, " N m/rad")
        );
        found.push(Matched {
            iterations: n,
            target,
            alpha_b: alpha,
            bend_stiffness: stiffness,
        });
    }
    Ok(found)
}

/// The stiffness each alpha_b row of the grid amounts to at its iteration count: the stiffness
/// whose settled psi (no push, the scene's twist) is the alpha's. Printed.
fn print_equivalents(scene: &Scene, rows: &[TuneRow]) -> anyhow::Result<()> {
    let mut cases: Vec<(f32, u32)> = (rows.iter())
        .filter_map(|r| match r.copy.bend {
            Softness::Alpha(a) => Some((a, r.copy.iterations)),
            Softness::Stiffness(_) => None,
        })
        .collect();
    cases.dedup();
    cases.sort_by(|a, b| (a.1, a.0).partial_cmp(&(b.1, b.0)).unwrap());
    cases.dedup();
    if cases.is_empty() {
        return Ok(());
    }
    let twist = tune::scene_twist(scene)?;
    report!(
        "  what alpha_b amounts to (dt {} s, {} substep(s), {}; measured: the stiffness that \
         settles where the alpha does):",
        scene.def.dt,
        scene.def.substeps,
        twist.label("twist")
    );
    // per case: None if the alpha does not settle, else its psi and the matching stiffness
    type Equivalent = Option<(f32, Option<(f32, f32)>)>;
    let results: Vec<anyhow::Result<Equivalent>> = (cases.par_iter())
        .map(|&(alpha, n)| {
            if alpha == 0.0 {
                return Ok(None); // no bend resistance at all: nothing to match
            }
            let setting = RodSetting {
                bend: Softness::Alpha(alpha),
                twist,
                bend_damping: None,
                twist_damping: None,
            };
            let frames = Some(tune::matching_frames(scene));
            let Some(psi) = tune::settled_psi(scene, setting, n, frames)? else {
                return Ok(None);
            };
            let tolerance = tune::match_tolerance(psi);
            let k = tune::match_psi(scene, psi, MatchBy::BendStiffness, twist, n, tolerance)?;
            Ok(Some((psi, k)))
        })
        .collect();
    let seconds = tune::matching_frames(scene) as f32 * scene.def.dt;
    for (&(alpha, n), result) in cases.iter().zip(results) {
        let line = match result? {
            // The free rod folds under gravity; past psi = pi eq. 6 and 9 read its mirror arc
            // (README, the rod's limits), so its "settled" psi (0.70 rad in passive bending)
            // would pass for a stiffness of 58 N m/rad.
            None if alpha == 0.0 => "no bend resistance: bend_stiffness 0 (the rod folds)".into(),
            None => format!("does not settle in {seconds:.0} s"),
            Some((psi, k)) => {
                let k = k.map_or("out of reach".into(), |(k, _)| format!("{k:.1} N m/rad"));
                format!("settles at psi {psi:.4} rad = bend_stiffness {k}")
            }
        };
        report!("    alpha_b {alpha:<7} at {n:>3} iterations: {line}");
    }
    Ok(())
}

/// `rodlab tune`.
pub fn tune(args: &TuneArgs) -> anyhow::Result<()> {
    let scene = Scene::load(&args.scene)?;
    let name = scene.name();
    if args.match_psi.is_some() || args.match_spine.is_some() {
        report!("== tune {name}: matching the bend");
        match_bend(args, &scene)?;
        return Ok(());
    }
    let config = args.config();
    run_grid(&scene, &config, &args.out)?;
    Ok(())
}

/// The grid of `config` on `scene` into `out`: recording, CSV, chart; returns the rows.
pub fn run_grid(scene: &Scene, config: &TuneConfig, out: &Path) -> anyhow::Result<Vec<TuneRow>> {
    let name = scene.name();
    let all = tune::copies(config, scene.def.iterations);
    let mine: Vec<_> = all
        .iter()
        .filter(|c| config.shard.takes(c.index))
        .cloned()
        .collect();
    report!(
        "== tune {name}: {} of {} copies ({} bend x {} twist x {} iteration counts)",
        mine.len(),
        all.len(),
        config.bend.len(),
        config.twist.len(),
        all.len() / (config.bend.len() * config.twist.len()).max(1)
    );
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let stem = out.join(format!("tune{}", config.shard.suffix()));
    let rrd = stem.with_extension("rrd");
    let mut recorder = TuneRecorder::create(&rrd, &name, &all, &mine)?;
    let (rows, traces) = tune::run_grid(scene, config, &mut |frame, labs| {
        recorder.frame(frame, labs)
    })?;
    report!(
        "  {:<50} {:>9} {:>9} {:>10} {:>9} {:>9} {:>9}",
        "copy",
        "psi rad",
        "tau rad",
        "overshoot",
        "psi s",
        "tau s",
        "disl cm"
    );
    for r in &rows {
        match &r.failed {
            None => report!(
                "  {:<50} {:>9.4} {:>9.4} {:>10.4} {:>9.2} {:>9.2} {:>9.4}",
                r.copy.label(),
                r.final_psi,
                r.final_tau,
                r.psi_overshoot,
                r.psi_settling_s,
                r.tau_settling_s,
                r.mean_dislocation_cm
            ),
            Some(e) => report!("  {:<50} failed: {e}", r.copy.label()),
        }
    }
    let csv = tune::to_csv(&rows);
    let write = |path: PathBuf, bytes: &[u8]| {
        std::fs::write(&path, bytes).with_context(|| format!("cannot write {}", path.display()))
    };
    write(stem.with_extension("csv"), csv.as_bytes())?;
    let chart = tune::chart(&name, &rows);
    write(stem.with_extension("svg"), chart.to_svg().as_bytes())?;
    let png = chart.to_png()?;
    write(stem.with_extension("png"), &png)?;
    recorder.finish(&traces, &rows, &csv, &png)?;
    report!("  -> {} (and .csv, .svg, .png)", rrd.display());
    if config.shard == Shard::ALL {
        print_equivalents(scene, &rows)?;
    } else {
        report!("  (the alpha-to-stiffness equivalents are printed by an unsharded run)");
    }
    Ok(rows)
}
