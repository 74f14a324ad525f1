//! `rodlab sweep SCENE`: speed against accuracy.
//!
//! The scene is run headless once per combination of named method, spine, joint flavour and
//! the values listed for any method setting ([`SettingLists`]; `rodlab settings` lists them),
//! iterations innermost. Each run measures
//! - the cost: the median wall time of `World::step` over the frames after a warm-up, pooled
//!   over `repeats` runs (the residuals are deterministic, only the time varies);
//! - the accuracy: the residual after each frame (paper Fig. 8) per ragdoll, as the mean and the
//!   maximum over frames and ragdolls of the dislocation (cm) and the angular violation (rad).
//!
//! A method is a spine and a joint flavour (`rod/exact`), followed by the declared label of
//! each method setting that differs from the paper's (`rod/exact simd x4 warm0.25 soft30Hz`),
//! or a named method and its spine (`rod game`) followed by the settings that differ from the
//! method's own; its line on the chart runs through its iteration counts, so the
//! speed/accuracy frontier is the lower-left envelope of the lines.
//! A run that stops (NaN or an explosion) keeps its row, with the error, and no residual.
//!
//! CSV columns (`recordings/<scene>_sweep.csv`, one row per run, header first):
//!
//! | column | meaning |
//! |---|---|
//! | `method` | the line's label, as above (` block`: the rod's bend and twist as one block) |
//! | `spine` | chain3, rod or single (a game character: rig, rod or single) |
//! | `joint` | cheap or exact |
//! | one column per method setting | its value in the run, named as in scene files (`solver`, `substeps`, ..., `dt`, `iterations`) |
//! | `step_us` | median time per step (microseconds) |
//! | `mean_dislocation_cm`, `max_dislocation_cm` | per ragdoll, over frames |
//! | `mean_angular_rad`, `max_angular_rad` | per ragdoll, over frames |
//! | `max_overlap_cm` | the deepest overlap of the shapes over the run, found afresh on each frame's final poses (0 without contacts; [`FrameMetrics::max_overlap_cm`]) |
//! | `failed` | empty, or why the run stopped |

use std::time::Instant;

use crate::chart::{Chart, Series};
use crate::constraint::{BendTwist, JointFlavour};
use crate::lab::Lab;
use crate::metrics::FrameMetrics;
use crate::ragdoll::SpineKind;
use crate::scene::{Method, Scene};
use crate::sim::Overrides;
use crate::world::Settings;

mod combinations;
mod features;
pub mod layouts;
mod table;

pub use combinations::{
    combinations, method_label, named_method_label, SettingLists, DEFAULT_ITERATIONS,
};
pub use features::{feature_costs, FeatureCost};
pub use table::{parse_csv, to_csv};

/// What to sweep.
#[derive(Clone, Debug)]
pub struct SweepConfig {
    /// Named methods, each a line of its own beside the others (empty: the scene's own
    /// method); the lists that are empty keep each method's settings, and `iterations`
    /// counts solves per frame: a method at `s` substeps runs `max(1, n / s)` iterations each.
    pub methods: Vec<Method>,
    /// Spines; empty: the scene's `spines` (with single beside a humanoid's), else chain3, rod
    /// and single.
    pub spines: Vec<SpineKind>,
    /// Ball-and-socket joint flavours; empty keeps the scene's (or the method's).
    pub joints: Vec<JointFlavour>,
    /// The rod spine's bend and twist projections (sequential, the reference; block); empty
    /// keeps the scene's. Other spines run once.
    pub bend_twist: Vec<BendTwist>,
    /// The method settings' values, one dimension per non-empty list; `iterations` empty runs
    /// [`DEFAULT_ITERATIONS`].
    pub settings: SettingLists,
    /// Frames per run; `None` keeps the scene's.
    pub frames: Option<u32>,
    /// Runs per combination, pooled for the median step time.
    pub repeats: u32,
}

impl Default for SweepConfig {
    fn default() -> Self {
        SweepConfig {
            methods: Vec::new(),
            spines: vec![SpineKind::Chain3, SpineKind::Rod, SpineKind::Single],
            joints: vec![JointFlavour::Cheap, JointFlavour::Exact],
            bend_twist: Vec::new(),
            settings: SettingLists::default(),
            frames: None,
            repeats: 3,
        }
    }
}

/// One run of the sweep: a CSV row.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepRow {
    /// The line's label: `<spine>/<joint>` and its settings for rodlab's methods, the engine's
    /// name for a peer.
    pub method: String,
    /// Spine: chain3, rod or single (a game character: rig, rod or single).
    pub spine: String,
    /// cheap or exact for rodlab; the peer's joint kind for a peer.
    pub joint: String,
    /// The run's method settings (one CSV column each); a peer's row holds its time step and
    /// iterations over the defaults.
    pub settings: Settings,
    /// Median wall time (microseconds) of one `World::step` after the warm-up.
    pub step_us: f64,
    /// Dislocation per ragdoll (cm), mean over frames and ragdolls.
    pub mean_dislocation_cm: f64,
    /// Dislocation per ragdoll (cm), maximum over frames and ragdolls.
    pub max_dislocation_cm: f64,
    /// Angular violation per ragdoll (rad), mean over frames and ragdolls.
    pub mean_angular_rad: f64,
    /// Angular violation per ragdoll (rad), maximum over frames and ragdolls.
    pub max_angular_rad: f64,
    /// Deepest overlap of the shapes over the run (cm), found afresh each frame.
    pub max_overlap_cm: f64,
    /// Why the run stopped (NaN or an explosion); `None` if it ran to the end.
    pub failed: Option<String>,
}

impl SweepRow {
    /// A row for `method` at `settings` before it is measured.
    pub fn new(method: String, spine: String, joint: String, settings: Settings) -> Self {
        SweepRow {
            method,
            spine,
            joint,
            settings,
            step_us: 0.0,
            mean_dislocation_cm: 0.0,
            max_dislocation_cm: 0.0,
            mean_angular_rad: 0.0,
            max_angular_rad: 0.0,
            max_overlap_cm: 0.0,
            failed: None,
        }
    }
}

/// Runs one combination `repeats` times; `scene` is the scene as loaded.
pub fn run_one(scene: &Scene, overrides: &Overrides, repeats: u32) -> anyhow::Result<SweepRow> {
    let mut scene = scene.clone();
    overrides.apply(&mut scene.def);
    let def = &scene.def;
    let spine = overrides.spine.unwrap_or_default();
    let label = match overrides.method {
        Some(method) => named_method_label(method, spine, def),
        None => method_label(spine, def),
    };
    let mut settings = Settings::default();
    def.write_method_settings(&mut settings);
    let row = SweepRow::new(
        label,
        spine.to_string(),
        def.joint_flavour.to_string(),
        settings,
    );
    let frames = def.frames;
    time_and_measure(row, frames, repeats, || Ok(scene.build()?))
}

/// An engine the sweep can time frame by frame, with a rodlab lab to measure.
pub trait Timed {
    /// Advances one frame: the wall time of the engine's step alone (us), or why it stopped.
    fn step_timed(&mut self) -> Result<f64, String>;
    /// The lab whose residuals are measured after each frame (not timed).
    fn measured(&self) -> &Lab;
}

impl Timed for Lab {
    fn step_timed(&mut self) -> Result<f64, String> {
        let start = Instant::now();
        let stepped = self.step();
        let elapsed = start.elapsed().as_secs_f64() * 1e6;
        stepped.map(|()| elapsed).map_err(|e| e.to_string())
    }

    fn measured(&self) -> &Lab {
        self
    }
}

/// Fills `row`: runs `build()` for `frames` frames `repeats` times; the step time is the median
/// over the frames after a warm-up (a tenth of the run, at most 30 frames), pooled over the
/// repeats; the residuals come from the first repeat (they are deterministic). Shared by
/// rodlab's runs and the peer's, so both are measured the same way.
pub fn time_and_measure<T: Timed>(
    mut row: SweepRow,
    frames: u32,
    repeats: u32,
    mut build: impl FnMut() -> anyhow::Result<T>,
) -> anyhow::Result<SweepRow> {
    let warm_up = (frames / 10).min(30) as usize;
    let mut times = Vec::with_capacity(repeats as usize * frames as usize);
    let mut metrics = FrameMetrics::default();
    for repeat in 0..repeats.max(1) {
        let mut engine = build()?;
        let (mut sum_d, mut sum_a, mut count) = (0.0f64, 0.0f64, 0u64);
        let (mut max_d, mut max_a, mut max_overlap) = (0.0f64, 0.0f64, 0.0f64);
        for frame in 0..frames as usize {
            let elapsed = match engine.step_timed() {
                Ok(elapsed) => elapsed,
                Err(error) => {
                    row.failed = Some(error);
                    break;
                }
            };
            if frame >= warm_up {
                times.push(elapsed);
            }
            if repeat == 0 {
                metrics.measure(engine.measured());
                max_overlap = max_overlap.max(metrics.max_overlap_cm as f64);
                for r in &metrics.ragdolls {
                    sum_d += r.dislocation_cm as f64;
                    sum_a += r.angular_rad as f64;
                    max_d = max_d.max(r.dislocation_cm as f64);
                    max_a = max_a.max(r.angular_rad as f64);
                    count += 1;
                }
            }
        }
        if repeat == 0 {
            let n = count.max(1) as f64;
            row.mean_dislocation_cm = sum_d / n;
            row.mean_angular_rad = sum_a / n;
            row.max_dislocation_cm = max_d;
            row.max_angular_rad = max_a;
            row.max_overlap_cm = max_overlap;
        }
        if row.failed.is_some() {
            break;
        }
    }
    row.step_us = median(&mut times);
    Ok(row)
}

/// The median of `values` (sorted in place); NaN when empty.
pub fn median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    values.sort_unstable_by(f64::total_cmp);
    values[values.len() / 2]
}

/// Residual against time per step, one line per method (and time step, when several) through
/// its iteration counts; a method at several substeps or solvers has one line for each (the
/// label carries them), so iterations and substeps can be compared at equal cost.
pub fn chart(scene: &str, rows: &[SweepRow], machine: &str) -> Chart {
    Chart {
        title: format!("{scene}: residual after each frame against time per step ({machine})"),
        y_label: "mean dislocation per ragdoll (cm)".into(),
        ..lines(rows, |r| r.mean_dislocation_cm)
    }
}

/// The deepest overlap of the shapes over each run (found afresh on each frame's final poses)
/// against time per step, lines as in [`chart`]; `None` for a sweep without contacts.
pub fn overlap_chart(scene: &str, rows: &[SweepRow], machine: &str) -> Option<Chart> {
    rows.iter().any(|r| r.max_overlap_cm > 0.0).then(|| Chart {
        title: format!("{scene}: deepest overlap found afresh against time per step ({machine})"),
        y_label: "deepest overlap of the shapes over the run (cm)".into(),
        ..lines(rows, |r| r.max_overlap_cm)
    })
}

/// One line per method (and time step, when several) of `(step_us, y(row))` through its
/// iteration counts, log-log; the caller names the chart and its y axis.
fn lines(rows: &[SweepRow], y: impl Fn(&SweepRow) -> f64) -> Chart {
    let several_dts = rows.iter().any(|r| r.settings.dt != rows[0].settings.dt);
    let mut series: Vec<Series> = Vec::new();
    for row in rows.iter().filter(|r| r.failed.is_none()) {
        let label = if several_dts {
            format!("{} dt={:.4}", row.method, row.settings.dt)
        } else {
            row.method.clone()
        };
        let point = (row.step_us, y(row));
        match series.iter_mut().find(|s| s.label == label) {
            Some(s) => s.points.push(point),
            None => series.push(Series {
                label,
                points: vec![point],
            }),
        }
    }
    Chart {
        title: String::new(),
        x_label: "time per step (us, median)".into(),
        y_label: String::new(),
        x_log: true,
        y_log: true,
        series,
    }
}
