//! `rodlab layouts SCENE`: one method over many layouts of a `[drop]` block.
//!
//! A pile of ragdolls is chaotic: a rounding-level change gives another pile, so one layout is
//! one sample of whether a method comes to rest, keeps its overlap small or explodes. This runs
//! the scene headless once per layout seed (`--seed`) and spine and reports each run's end:
//!
//! | column | meaning |
//! |---|---|
//! | `seed`, `spine` | the layout and the spine |
//! | `at_rest` | no body's fastest surface point at or over the sleep speed at the end |
//! | `still_moving`, `fastest`, `fastest_speed` | how many were, the fastest and its speed (m/s) |
//! | `all_asleep_from` | the first frame with every body asleep (empty: never, or sleep off) |
//! | `deepest_overlap_cm` | the deepest overlap over the run, found afresh on each frame's final poses |
//! | `overlap_at_rest_mm` | the mean overlap of the points that overlap at the end ([`crate::world::World::overlap_at_rest`]) |
//! | `mean_dislocation_cm` | the total dislocation over all ragdolls, mean over frames |
//! | `settled_dislocation_cm` | the same over the run's second half, the pile settled |
//! | `lowest_centre_m` | the lowest any dynamic body's centre went over the run (m) |
//! | `state_hash` | the final state's hash ([`crate::world::World::state_hash`]), 16 hex digits |
//! | `failed` | empty, or why the run stopped (NaN, an explosion: frame, body, constraint) |

use std::path::Path;

use rayon::prelude::*;

use crate::ragdoll::SpineKind;
use crate::scene::{Overrides, Scene};
use crate::sim;

/// How one layout's run ended.
#[derive(Clone, Debug)]
pub struct LayoutRun {
    /// The `[drop]` block's seed.
    pub seed: u64,
    /// The spine of every ragdoll.
    pub spine: SpineKind,
    /// The run's end, or why it stopped.
    pub end: Result<LayoutEnd, String>,
}

/// The end of a run that finished.
#[derive(Clone, Debug, PartialEq)]
pub struct LayoutEnd {
    /// Bodies whose fastest surface point is at or over the sleep speed at the end.
    pub still_moving: usize,
    /// The fastest of them and its speed (m/s).
    pub fastest: Option<(String, f32)>,
    /// The first frame with every body asleep.
    pub all_asleep_from: Option<usize>,
    /// The deepest overlap over the run (cm), found afresh on each frame's final poses.
    pub deepest_overlap_cm: f32,
    /// The mean overlap (mm) of the contact points that overlap at the end.
    pub overlap_at_rest_mm: f32,
    /// The total dislocation over all ragdolls (cm), mean over frames.
    pub mean_dislocation_cm: f32,
    /// The same over the second half of the frames, the pile settled (cm).
    pub settled_dislocation_cm: f32,
    /// The lowest any dynamic body's centre went over the run (m).
    pub lowest_centre_m: f32,
    /// The final state's hash ([`crate::world::World::state_hash`]).
    pub state_hash: u64,
}

/// The CSV header (module docs).
pub const LAYOUTS_HEADER: &str = "seed,spine,at_rest,still_moving,fastest,fastest_speed,all_asleep_from,deepest_overlap_cm,overlap_at_rest_mm,mean_dislocation_cm,settled_dislocation_cm,lowest_centre_m,state_hash,failed";

/// Runs `scene` (its variant `variant`, then `overrides`) once per seed and spine, on several
/// threads; the runs in the order of `seeds`, then `spines`. `overrides` must not set the seed
/// or the spine, which this sets per run.
pub fn run_layouts(
    scene: &Path,
    variant: Option<&str>,
    overrides: &Overrides,
    seeds: &[u64],
    spines: &[SpineKind],
    mut done: impl FnMut(&LayoutRun) + Send,
) -> anyhow::Result<Vec<LayoutRun>> {
    anyhow::ensure!(
        overrides.seed.is_none() && overrides.spine.is_none(),
        "the layouts set the seed and the spine of each run"
    );
    let mut base = Scene::load(scene)?;
    if let Some(name) = variant {
        base = base.variant(name)?;
    }
    overrides.apply(&mut base.def);
    (overrides.check_on(&base)).map_err(|m| anyhow::anyhow!("{}: {m}", scene.display()))?;
    anyhow::ensure!(
        base.def.drop.is_some(),
        "{}: the scene has no [drop] block, so it has no layouts to vary",
        scene.display()
    );
    let defaults = base.def.default_spines();
    let spines = match spines.is_empty() {
        false => spines,
        true => &defaults[..],
    };
    let runs: Vec<(u64, SpineKind)> = seeds
        .iter()
        .flat_map(|&seed| spines.iter().map(move |&spine| (seed, spine)))
        .collect();
    let done = std::sync::Mutex::new(&mut done);
    let runs = runs.par_iter().map(|&(seed, spine)| {
        let mut scene = base.clone();
        Overrides {
            seed: Some(seed),
            spine: Some(spine),
            ..Default::default()
        }
        .apply(&mut scene.def);
        let run = LayoutRun {
            seed,
            spine,
            end: run_one(&scene),
        };
        (done.lock().unwrap_or_else(|p| p.into_inner()))(&run);
        run
    });
    Ok(runs.collect())
}

/// One layout's run to its end.
fn run_one(scene: &Scene) -> Result<LayoutEnd, String> {
    let mut lab = scene.build().map_err(|e| format!("{e:#}"))?;
    let mut lowest = f32::INFINITY;
    let mut observer = |lab: &crate::lab::Lab, _: &crate::metrics::FrameMetrics| {
        let dynamic = lab.world.bodies.iter().filter(|b| b.is_dynamic());
        lowest = dynamic.map(|b| b.position.y).fold(lowest, f32::min);
    };
    let report =
        sim::run(&mut lab, scene.def.frames, &mut observer).map_err(|e| format!("{e:#}"))?;
    let frames = report.total_dislocation_cm.len().max(1) as f32;
    let settled = &report.total_dislocation_cm[report.total_dislocation_cm.len() / 2..];
    Ok(LayoutEnd {
        still_moving: report.restless.len(),
        fastest: (report.restless.first()).map(|(name, r)| (name.clone(), r.point_speed)),
        all_asleep_from: report.awake_bodies.iter().position(|&n| n == 0),
        deepest_overlap_cm: report.max_overlap_cm,
        overlap_at_rest_mm: 1000.0 * lab.world.overlap_at_rest().2,
        mean_dislocation_cm: report.total_dislocation_cm.iter().sum::<f32>() / frames,
        settled_dislocation_cm: settled.iter().sum::<f32>() / settled.len().max(1) as f32,
        lowest_centre_m: lowest,
        state_hash: report.state_hash,
    })
}

/// The runs as CSV (module docs).
pub fn layouts_csv(runs: &[LayoutRun]) -> String {
    let rows = runs.iter().map(|run| {
        let mut row = vec![run.seed.to_string(), run.spine.to_string()];
        match &run.end {
            Ok(end) => {
                let (fastest, speed) = match &end.fastest {
                    Some((name, speed)) => (name.clone(), format!("{speed:.3}")),
                    None => (String::new(), String::new()),
                };
                row.extend([
                    (end.still_moving == 0).to_string(),
                    end.still_moving.to_string(),
                    fastest,
                    speed,
                    end.all_asleep_from.map_or(String::new(), |f| f.to_string()),
                    format!("{:.3}", end.deepest_overlap_cm),
                    format!("{:.3}", end.overlap_at_rest_mm),
                    format!("{:.3}", end.mean_dislocation_cm),
                    format!("{:.3}", end.settled_dislocation_cm),
                    format!("{:.3}", end.lowest_centre_m),
                    format!("{:016x}", end.state_hash),
                    String::new(),
                ]);
            }
            Err(why) => {
                row.extend(std::iter::repeat_n(String::new(), 11));
                row.push(why.clone());
            }
        }
        row
    });
    crate::csv_table::to_text(LAYOUTS_HEADER, rows)
}

/// A summary of the runs per spine: how many ended at rest, passed `overlap_cm` of overlap, or
/// stopped; as Markdown lines.
pub fn layouts_summary(runs: &[LayoutRun], overlap_cm: f32) -> Vec<String> {
    let mut spines: Vec<SpineKind> = Vec::new();
    for run in runs {
        if !spines.contains(&run.spine) {
            spines.push(run.spine);
        }
    }
    spines
        .iter()
        .map(|&spine| {
            let of: Vec<&LayoutRun> = runs.iter().filter(|r| r.spine == spine).collect();
            let ends: Vec<&LayoutEnd> = of.iter().filter_map(|r| r.end.as_ref().ok()).collect();
            let at_rest = ends.iter().filter(|e| e.still_moving == 0).count();
            let deep = ends
                .iter()
                .filter(|e| e.deepest_overlap_cm > overlap_cm)
                .count();
            let deepest = ends.iter().map(|e| e.deepest_overlap_cm).fold(0.0, f32::max);
            let resting = ends.iter().map(|e| e.overlap_at_rest_mm).fold(0.0, f32::max);
            format!(
                "- {spine}: {} layouts; at rest at the end {at_rest}; deepest overlap over {overlap_cm} cm {deep} (the deepest {deepest:.2} cm); mean overlap at the end at most {resting:.2} mm; stopped {}",
                of.len(),
                of.len() - ends.len()
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A stopped run keeps its row, with why, and counts as stopped, not as at rest.
    #[test]
    fn a_stopped_run_keeps_its_row_and_its_reason() {
        let end = LayoutEnd {
            still_moving: 0,
            fastest: None,
            all_asleep_from: Some(300),
            deepest_overlap_cm: 1.5,
            overlap_at_rest_mm: 0.8,
            mean_dislocation_cm: 2.0,
            settled_dislocation_cm: 1.5,
            lowest_centre_m: 0.04,
            state_hash: 0xabc,
        };
        let runs = [
            LayoutRun {
                seed: 1,
                spine: SpineKind::Rod,
                end: Ok(end),
            },
            LayoutRun {
                seed: 2,
                spine: SpineKind::Rod,
                end: Err("frame 9: body \"b\" exploded, badly".into()),
            },
        ];
        let csv = layouts_csv(&runs);
        let rows = crate::csv_table::read(&csv, LAYOUTS_HEADER).unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(&rows[0].1[2], "true");
        assert_eq!(&rows[0].1[6], "300");
        assert_eq!(&rows[0].1[8], "0.800");
        assert_eq!(&rows[0].1[12], "0000000000000abc");
        assert_eq!(&rows[1].1[13], "frame 9: body \"b\" exploded, badly");
        assert_eq!(&rows[1].1[2], "");
        assert_eq!(
            layouts_summary(&runs, 1.0),
            ["- rod: 2 layouts; at rest at the end 1; deepest overlap over 1 cm 1 (the deepest 1.50 cm); mean overlap at the end at most 0.80 mm; stopped 1"]
        );
    }
}
