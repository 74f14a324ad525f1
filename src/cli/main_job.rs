//! The main job (`rodlab`, `rodlab all`): every scene, per spine and `[[variant]]`, into
//! recordings, with a residual summary; and the list of files it writes (`rodlab outputs`).

use std::path::{Path, PathBuf};

use anyhow::Context as _;

use crate::constraint::BendTwist;
use crate::ragdoll::SpineKind;
use crate::record;
use crate::scene::Scene;
use crate::shard::Shard;
use crate::sim::{Overrides, RunReport};
use crate::sweep::SettingLists;

use super::run::{load_scene, record_kinematics_scene, record_scene};
use super::summary::print_summary;
use super::{layouts, stop, stress, sweep, tune};

/// The main job: every scene recorded, then the passive-bending sweep.
/// Scenes the main job sweeps, besides recording every scene.
const SWEPT_SCENES: [&str; 2] = ["passive_bending", "ragdoll_drop"];

/// The files [`main_job`] writes: every scene's recordings (one per spine and variant), each
/// swept scene's table, chart and recording and feature costs, the tuning grid and the stress
/// table (the stress suite's recordings of unstable runs vary, and are not listed).
pub(super) fn main_job_outputs(scenes: &Path, out: &Path) -> anyhow::Result<Vec<PathBuf>> {
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
    // the drop has contacts: its deepest overlap is charted too
    for ext in ["svg", "png"] {
        files.push(out.join(format!("{}_sweep_overlap.{ext}", SWEPT_SCENES[1])));
    }
    for ext in ["rrd", "csv", "svg", "png"] {
        files.push(out.join(format!("tune.{ext}")));
    }
    files.extend([out.join("stress.md"), out.join("stress.csv")]);
    for (_, variant, _) in SURVEYED_LAYOUTS {
        let drop = scenes.join(format!("{}.toml", SWEPT_SCENES[1]));
        let name = layouts::layouts_name(&drop, Some(variant));
        files.extend(["md", "csv"].map(|ext| out.join(format!("{name}.{ext}"))));
    }
    Ok(files)
}

pub(super) fn main_job() -> anyhow::Result<()> {
    let (scenes, out) = (Path::new("scenes"), Path::new("recordings"));
    run_all(scenes, out, &Overrides::default())?;
    if stop::requested() {
        return Ok(());
    }
    let [bending, drop] = SWEPT_SCENES.map(|name| scenes.join(format!("{name}.toml")));
    let path = bending;
    // the paper's one step a frame (the reference line) beside 4 substeps, on one cost axis,
    // and the rod's bend and twist one after the other (the reference) beside one block
    let config = crate::sweep::SweepConfig {
        settings: SettingLists {
            substeps: vec![1, 4],
            ..Default::default()
        },
        bend_twist: vec![BendTwist::Sequential, BendTwist::Block],
        ..Default::default()
    };
    sweep(&path, &config, None, Shard::ALL, out)?;
    if stop::requested() {
        return Ok(());
    }
    // the drop: the paper's method as the reference line beside the game and tight methods,
    // at budgets of 4, 20 and 40 solves a frame, over the fall, the landing and the first
    // seconds of the pile
    let config = crate::sweep::SweepConfig {
        methods: crate::scene::Method::ALL.to_vec(),
        settings: SettingLists {
            iterations: vec![4, 20, 40],
            ..Default::default()
        },
        spines: vec![SpineKind::Chain3, SpineKind::Rod],
        joints: Vec::new(),
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
    stress(out)?;
    // where the drop's variants fail, over layouts rather than on the scene's one
    for (seeds, variant, frames) in SURVEYED_LAYOUTS {
        if stop::requested() {
            return Ok(());
        }
        let seeds: Vec<u64> = seeds.collect();
        let what = layouts::Survey {
            variant: Some(variant),
            seeds: &seeds,
            spines: &[SpineKind::Chain3, SpineKind::Rod],
            overlap_cm: 1.0,
        };
        let overrides = Overrides {
            frames,
            ..Default::default()
        };
        layouts::survey(&drop, &what, &overrides, out)?;
    }
    Ok(())
}

/// The drop's variants the main job runs over layouts ([`layouts::survey`]): seeds, variant,
/// frames (None: the scene's). The at-rest pile over its 10 s; the landing of the variant
/// that keeps overlap within 1 cm, over the test's 150 frames.
const SURVEYED_LAYOUTS: [(std::ops::RangeInclusive<u64>, &str, Option<u32>); 2] =
    [(1..=16, "game", None), (1..=16, "tight", Some(150))];

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

pub(super) fn run_all(
    scenes_dir: &Path,
    out_dir: &Path,
    overrides: &Overrides,
) -> anyhow::Result<()> {
    let paths = scene_files(scenes_dir)?;
    let mut failures = Vec::new();
    for path in &paths {
        if stop::requested() {
            break;
        }
        let result = load_scene(path, None, overrides).and_then(|mut scene| {
            // heavy scenes give the main job a shorter run (`ci_frames`), unless --frames
            if let (None, Some(n)) = (overrides.frames, scene.def.ci_frames) {
                report!(
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
                if variant.def.kinematics.is_some() {
                    record_kinematics_scene(&variant, &record::save_to(&out, &variant)?)?;
                    report!(
                        "  -> {} ({:.1} s)",
                        out.display(),
                        started.elapsed().as_secs_f32()
                    );
                    continue;
                }
                let report = record_scene(&variant, record::save_to(&out, &variant)?)?;
                print_summary(&name, &variant, &report);
                report!(
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
            note!("error: {e:#}");
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
    for name in scene.variant_names() {
        let mut method = scene.variant(name)?;
        overrides.apply(&mut method.def);
        (overrides.check_on(&method))
            .map_err(|m| anyhow::anyhow!("{}: [[variant]] {name}: {m}", scene.path.display()))?;
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
    report!(
        "  total dislocation, mean over frames: {name_a} {:.3} cm, {name_b} {:.3} cm; {name_b} below {name_a} in {:.1}% of frames",
        mean(a),
        mean(b),
        100.0 * better as f32 / frames.max(1) as f32
    );
}
