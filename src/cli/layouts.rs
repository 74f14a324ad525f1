//! `rodlab layouts`: one method over many layouts of a drop ([`crate::sweep::layouts`]), its
//! table printed and saved.

use std::path::Path;

use anyhow::Context as _;

use crate::sim::Overrides;
use crate::sweep::layouts::{layouts_csv, layouts_summary, run_layouts, LayoutRun};

use super::args::LayoutsArgs;
use super::sweep::Progress;

/// Runs the layouts and writes `<out>/<scene>[_<variant>]_layouts.md` and `.csv`.
pub(super) fn layouts(args: &LayoutsArgs) -> anyhow::Result<()> {
    let overrides: Overrides = (&args.overrides).into();
    if overrides.seed.is_some() || overrides.spine.is_some() {
        anyhow::bail!("--seed and --spine: the layouts take --seeds and --spines");
    }
    let stem = args.scene.file_stem().unwrap_or_default().to_string_lossy();
    let name = match &args.variant {
        Some(variant) => format!("{stem}_{variant}_layouts"),
        None => format!("{stem}_layouts"),
    };
    let runs_total = args.seeds.0.len() * args.spines.len();
    let mut progress = Progress::new(runs_total);
    let runs = run_layouts(
        &args.scene,
        args.variant.as_deref(),
        &overrides,
        &args.seeds.0,
        &args.spines,
        |run| progress.show(&format!("seed {} {}", run.seed, run.spine)),
    )?;
    progress.finish();
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let csv = args.out.join(format!("{name}.csv"));
    std::fs::write(&csv, layouts_csv(&runs))
        .with_context(|| format!("cannot write {}", csv.display()))?;
    let summary = layouts_summary(&runs, args.overlap_cm);
    let md = args.out.join(format!("{name}.md"));
    std::fs::write(&md, markdown(&args.scene, args, &summary, &runs))
        .with_context(|| format!("cannot write {}", md.display()))?;
    for line in &summary {
        println!("{line}");
    }
    println!("  -> {}, {}", md.display(), csv.display());
    Ok(())
}

/// The summary and one row per run.
fn markdown(scene: &Path, args: &LayoutsArgs, summary: &[String], runs: &[LayoutRun]) -> String {
    let mut text = format!(
        "# Layouts of {}{}\n\n{}\n\n| seed | spine | at rest | still moving (fastest) | all asleep from frame | deepest overlap | mean dislocation |\n|---|---|---|---|---|---|---|\n",
        scene.display(),
        args.variant.as_ref().map_or(String::new(), |v| format!(", variant {v}")),
        summary.join("\n")
    );
    for run in runs {
        let row = match &run.end {
            Ok(end) => format!(
                "{} | {} | {} | {:.2} cm | {:.2} cm",
                if end.still_moving == 0 { "yes" } else { "no" },
                match &end.fastest {
                    Some((body, speed)) => format!("{} ({body} {speed:.2} m/s)", end.still_moving),
                    None => "0".into(),
                },
                end.all_asleep_from.map_or("-".into(), |f| f.to_string()),
                end.deepest_overlap_cm,
                end.mean_dislocation_cm
            ),
            Err(why) => format!("stopped: {} | | | |", why.replace('\n', " ")),
        };
        text += &format!("| {} | {} | {row} |\n", run.seed, run.spine);
    }
    text
}
