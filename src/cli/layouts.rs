//! `rodlab layouts`: one method over many layouts of a drop ([`crate::sweep::layouts`]), its
//! table printed and saved.

use std::path::Path;

use anyhow::Context as _;

use crate::ragdoll::SpineKind;
use crate::sim::Overrides;
use crate::sweep::layouts::{layouts_csv, layouts_summary, run_layouts, LayoutRun};

use super::args::LayoutsArgs;
use super::sweep::Progress;

/// `rodlab layouts`: the arguments checked, then [`survey`].
pub(super) fn layouts(args: &LayoutsArgs) -> anyhow::Result<()> {
    let overrides: Overrides = (&args.overrides).into();
    if overrides.seed.is_some() || overrides.spine.is_some() {
        anyhow::bail!("--seed and --spine: the layouts take --seeds and --spines");
    }
    let spines = match args.spines.is_empty() {
        true => crate::scene::Scene::load(&args.scene)?.def.default_spines(),
        false => args.spines.clone(),
    };
    let survey_args = Survey {
        variant: args.variant.as_deref(),
        seeds: &args.seeds.0,
        spines: &spines,
        overlap_cm: args.overlap_cm,
    };
    survey(&args.scene, &survey_args, &overrides, &args.out)
}

/// What a survey runs: the variant, the seeds and spines, and the overlap it counts.
pub(super) struct Survey<'a> {
    pub variant: Option<&'a str>,
    pub seeds: &'a [u64],
    pub spines: &'a [SpineKind],
    pub overlap_cm: f32,
}

/// Runs the layouts and writes `<out>/<scene>[_<variant>]_layouts.md` and `.csv`.
pub(super) fn survey(
    scene: &Path,
    what: &Survey,
    overrides: &Overrides,
    out: &Path,
) -> anyhow::Result<()> {
    let name = layouts_name(scene, what.variant);
    let mut progress = Progress::new(what.seeds.len() * what.spines.len());
    let runs = run_layouts(
        scene,
        what.variant,
        overrides,
        what.seeds,
        what.spines,
        |run| progress.show(&format!("seed {} {}", run.seed, run.spine)),
    )?;
    progress.finish();
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let csv = out.join(format!("{name}.csv"));
    std::fs::write(&csv, layouts_csv(&runs))
        .with_context(|| format!("cannot write {}", csv.display()))?;
    let summary = layouts_summary(&runs, what.overlap_cm);
    let md = out.join(format!("{name}.md"));
    std::fs::write(&md, markdown(scene, what.variant, &summary, &runs))
        .with_context(|| format!("cannot write {}", md.display()))?;
    for line in &summary {
        report!("{line}");
    }
    report!("  -> {}, {}", md.display(), csv.display());
    Ok(())
}

/// `<scene>_layouts`, or `<scene>_<variant>_layouts`.
pub(super) fn layouts_name(scene: &Path, variant: Option<&str>) -> String {
    let stem = scene.file_stem().unwrap_or_default().to_string_lossy();
    match variant {
        Some(variant) => format!("{stem}_{variant}_layouts"),
        None => format!("{stem}_layouts"),
    }
}

/// The summary and one row per run.
fn markdown(scene: &Path, variant: Option<&str>, summary: &[String], runs: &[LayoutRun]) -> String {
    let mut text = format!(
        "# Layouts of {}{}\n\n{}\n\n| seed | spine | at rest | still moving (fastest) | all asleep from frame | deepest overlap | mean overlap at the end | mean dislocation |\n|---|---|---|---|---|---|---|---|\n",
        scene.display(),
        variant.map_or(String::new(), |v| format!(", variant {v}")),
        summary.join("\n")
    );
    for run in runs {
        let row = match &run.end {
            Ok(end) => format!(
                "{} | {} | {} | {:.2} cm | {:.2} mm | {:.2} cm",
                if end.still_moving == 0 { "yes" } else { "no" },
                match &end.fastest {
                    Some((body, speed)) => format!("{} ({body} {speed:.2} m/s)", end.still_moving),
                    None => "0".into(),
                },
                end.all_asleep_from.map_or("-".into(), |f| f.to_string()),
                end.deepest_overlap_cm,
                end.overlap_at_rest_mm,
                end.mean_dislocation_cm
            ),
            Err(why) => format!("stopped: {} | | | | |", why.replace('\n', " ")),
        };
        text += &format!("| {} | {} | {row} |\n", run.seed, run.spine);
    }
    text
}
