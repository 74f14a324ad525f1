//! `rodlab tune`: the rod's bend and twist settings side by side, for tuning them by eye.
//!
//! Every combination of the listed bend settings (rows), twist settings (columns) and iteration
//! counts (layers) becomes one copy of the scene's rod-spine ragdoll on a grid, each in its own
//! world (so each copy keeps its own iteration count), stepped in lockstep. Every copy does the
//! same motion: the scene's (for passive bending, the slump under gravity) plus a twist push,
//! an angular velocity about the rod's tangent given to the chest at the start, so both `psi`
//! and `tau` move. Per copy the summary holds the settled bend and twist (means over the last
//! [`SETTLED_WINDOW_S`]), the bend's overshoot, the settling times (to within 2% of the final
//! value) and the mean dislocation.
//!
//! A setting is the paper's relaxation alpha (a fraction removed per iteration, so its
//! stiffness depends on the budget) or a stiffness in N m/rad (compliance form, the same at any
//! budget, [`crate::constraint::rod`]). [`match_psi`] bisects either until the settled bend
//! matches a wanted angle, which also measures the stiffness an alpha amounts to.
//!
//! [`Shard`] splits the combinations between processes.
//!
//! No recording here: [`run_grid`] reports each frame to an observer (the CLI's records it,
//! [`crate::record::tune`]).

use anyhow::{bail, Context as _};
use rayon::prelude::*;

use crate::chart::{Chart, Series};
use crate::constraint::Constraint;
use crate::lab::Lab;
use crate::math::Vec3;
use crate::ragdoll::SpineKind;
use crate::scene::{RagdollDef, Scene};
pub use crate::shard::Shard;

/// The settled value of a series is its mean over this last stretch of the run (s).
pub const SETTLED_WINDOW_S: f32 = 0.5;
/// Settling: within this fraction of the final value from then on.
pub const SETTLING_BAND: f32 = 0.02;
/// A run has settled (for matching) if over the last [`SETTLED_WINDOW_S`] it stays within this
/// fraction of its mean there, or within [`SETTLED_BAND_RAD`] of it.
pub const SETTLED_BAND: f32 = 0.05;
/// Absolute form of [`SETTLED_BAND`] (rad), for settled values near zero.
pub const SETTLED_BAND_RAD: f32 = 0.002;
/// Distance between neighbouring copies on the grid (m).
pub const GRID_SPACING: f32 = 1.2;

/// One bend or twist setting of the rod.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Softness {
    /// The paper's relaxation alpha in [0, 1] (eq. 11, 13).
    Alpha(f32),
    /// Stiffness (N m/rad), solved in compliance form.
    Stiffness(f32),
}

impl Softness {
    /// `alpha_b 0.005` or `bend_stiffness 200`, with `part` "bend" or "twist".
    pub fn label(self, part: &str) -> String {
        match self {
            Softness::Alpha(a) => format!("alpha_{} {a}", &part[..1]),
            Softness::Stiffness(k) => format!("{part}_stiffness {k}"),
        }
    }

    /// (kind, value) for the CSV: `alpha` or `stiffness`.
    fn columns(self) -> (&'static str, f32) {
        match self {
            Softness::Alpha(a) => ("alpha", a),
            Softness::Stiffness(k) => ("stiffness", k),
        }
    }
}

/// What `rodlab tune` varies.
#[derive(Clone, Debug)]
pub struct TuneConfig {
    /// Rows of the grid.
    pub bend: Vec<Softness>,
    /// Columns of the grid.
    pub twist: Vec<Softness>,
    /// Damping (N m s/rad) of the stiffness settings; none for alphas.
    pub bend_damping: Option<f32>,
    /// Damping (N m s/rad) of the twist stiffness settings; none for alphas.
    pub twist_damping: Option<f32>,
    /// Layers of the grid; empty: the scene's iteration count.
    pub iterations: Vec<u32>,
    /// Frames per copy; default the scene's.
    pub frames: Option<u32>,
    /// Angular velocity (rad/s) about the rod's tangent given to the chest at the start.
    pub twist_push: f32,
    /// Which of the combinations this process runs.
    pub shard: Shard,
}

impl Default for TuneConfig {
    /// The default grid: 5 alpha_b x 4 alpha_t at the scene's iterations.
    fn default() -> Self {
        TuneConfig {
            bend: [0.0, 0.002, 0.005, 0.02, 0.1].map(Softness::Alpha).to_vec(),
            twist: [0.0, 0.1, 0.5, 1.0].map(Softness::Alpha).to_vec(),
            bend_damping: None,
            twist_damping: None,
            iterations: Vec::new(),
            frames: None,
            twist_push: 2.0,
            shard: Shard::ALL,
        }
    }
}

/// One copy of the grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Copy {
    /// Index among all combinations (shards split on it).
    pub index: usize,
    /// Row of the grid: index into the bend settings.
    pub row: usize,
    /// Column of the grid: index into the twist settings.
    pub column: usize,
    /// Layer of the grid: index into the iteration counts.
    pub layer: usize,
    /// The copy's bend setting.
    pub bend: Softness,
    /// The copy's twist setting.
    pub twist: Softness,
    /// The copy's solver iterations per substep.
    pub iterations: u32,
    /// Where the copy stands, added to the scene's positions.
    pub offset: Vec3,
}

impl Copy {
    /// The copy's settings for legends, e.g. `alpha_b 0.005, alpha_t 0.5, 20 it`.
    pub fn label(&self) -> String {
        format!(
            "{}, {}, {} it",
            self.bend.label("bend"),
            self.twist.label("twist"),
            self.iterations
        )
    }

    /// Entity path below a plot or the grid: `bend_0/twist_2/iter_1`.
    pub fn entity(&self) -> String {
        format!(
            "bend_{}/twist_{}/iter_{}",
            self.row, self.column, self.layer
        )
    }
}

/// The whole grid, in combination order (layer, then row, then column); layers stand side by
/// side along x, a column apart.
pub fn copies(config: &TuneConfig, scene_iterations: u32) -> Vec<Copy> {
    let iterations = if config.iterations.is_empty() {
        vec![scene_iterations]
    } else {
        config.iterations.clone()
    };
    let columns = config.twist.len();
    let mut out = Vec::new();
    for (layer, &n) in iterations.iter().enumerate() {
        for (row, &bend) in config.bend.iter().enumerate() {
            for (column, &twist) in config.twist.iter().enumerate() {
                let x = (layer * (columns + 1) + column) as f32 * GRID_SPACING;
                out.push(Copy {
                    index: out.len(),
                    row,
                    column,
                    layer,
                    bend,
                    twist,
                    iterations: n,
                    offset: Vec3::new(x, 0.0, row as f32 * GRID_SPACING),
                });
            }
        }
    }
    out
}

/// The ragdoll `tune` copies: the scene's first rod-spine ragdoll, else its first ragdoll
/// given the rod spine.
fn tuned_ragdoll(scene: &Scene) -> anyhow::Result<RagdollDef> {
    let ragdolls = &scene.def.ragdoll;
    let Some(first) = ragdolls
        .iter()
        .find(|r| r.spine == SpineKind::Rod)
        .or(ragdolls.first())
    else {
        bail!("{}: no [[ragdoll]] to tune", scene.path.display());
    };
    let mut ragdoll = first.clone();
    ragdoll.spine = SpineKind::Rod;
    Ok(ragdoll)
}

/// The twist setting of the scene's tuned ragdoll (its `twist_stiffness`, else its `alpha_t`,
/// else the rod spine's default): what matching holds the twist at unless told otherwise.
pub fn scene_twist(scene: &Scene) -> anyhow::Result<Softness> {
    let ragdoll = tuned_ragdoll(scene)?;
    Ok(match (ragdoll.twist_stiffness, ragdoll.alpha_t) {
        (Some(k), _) => Softness::Stiffness(k),
        (None, Some(a)) => Softness::Alpha(a),
        (None, None) => Softness::Alpha(crate::ragdoll::RodParams::default().alpha_twist),
    })
}

/// One rod setting: the bend and twist of the tuned ragdoll, with their damping.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RodSetting {
    /// Bend setting: alpha_b (eq. 11) or a stiffness.
    pub bend: Softness,
    /// Twist setting: alpha_t (eq. 12-13) or a stiffness.
    pub twist: Softness,
    /// Damping (N m s/rad) of a bend stiffness; ignored with an alpha.
    pub bend_damping: Option<f32>,
    /// Damping (N m s/rad) of a twist stiffness; ignored with an alpha.
    pub twist_damping: Option<f32>,
}

fn set_softness(
    softness: Softness,
    damping: Option<f32>,
    alpha: &mut Option<f32>,
    stiffness: &mut Option<f32>,
    damping_field: &mut Option<f32>,
) {
    match softness {
        Softness::Alpha(a) => (*alpha, *stiffness, *damping_field) = (Some(a), None, None),
        Softness::Stiffness(k) => (*alpha, *stiffness, *damping_field) = (None, Some(k), damping),
    }
}

/// The scene with only the tuned ragdoll (and the scene's bodies and joints) at `offset`, with
/// `setting`, `iterations` and `frames`; built, and the twist push given.
pub fn build_copy(
    scene: &Scene,
    setting: RodSetting,
    iterations: u32,
    frames: Option<u32>,
    offset: Vec3,
    twist_push: f32,
) -> anyhow::Result<Lab> {
    let mut scene = scene.clone();
    let mut ragdoll = tuned_ragdoll(&scene)?;
    let shift = |p: &mut [f32; 3]| *p = (Vec3::from(*p) + offset).to_array();
    shift(&mut ragdoll.position);
    let r = &mut ragdoll;
    set_softness(
        setting.bend,
        setting.bend_damping,
        &mut r.alpha_b,
        &mut r.bend_stiffness,
        &mut r.bend_damping,
    );
    set_softness(
        setting.twist,
        setting.twist_damping,
        &mut r.alpha_t,
        &mut r.twist_stiffness,
        &mut r.twist_damping,
    );
    let def = &mut scene.def;
    def.ragdoll = vec![ragdoll];
    def.body.iter_mut().for_each(|b| shift(&mut b.position));
    def.joint.iter_mut().for_each(|j| shift(&mut j.anchor));
    def.iterations = iterations;
    def.frames = frames.unwrap_or(def.frames);
    let mut lab = scene
        .build()
        .with_context(|| format!("{}: building a tuning copy", scene.path.display()))?;
    let world = &mut lab.world;
    let spine = world.constraints.iter().find_map(|c| match c {
        Constraint::Rod(rod) => Some((rod.body_b, rod.local_frame_b)),
        _ => None,
    });
    let Some((chest, frame)) = spine else {
        bail!("{}: the tuned ragdoll has no rod", scene.path.display());
    };
    let tangent = world.body(chest).orientation * frame * Vec3::X;
    world.body_mut(chest).angular_velocity += twist_push * tangent;
    Ok(lab)
}

/// What one copy did, frame by frame (index 0 is the first step's end).
#[derive(Clone, Debug, Default)]
pub struct Trace {
    /// The rod's bend psi per frame (rad).
    pub psi: Vec<f32>,
    /// The rod's twist tau per frame (rad).
    pub tau: Vec<f32>,
    /// Kinetic plus gravitational potential energy (J).
    pub energy: Vec<f32>,
    /// The ragdoll's dislocation per frame, summed over its constraints (cm).
    pub dislocation_cm: Vec<f32>,
    /// Why the copy stopped, with the frame, if it failed.
    pub failed: Option<String>,
}

impl Trace {
    fn record(&mut self, lab: &Lab) {
        let world = &lab.world;
        let state = world
            .rod_states()
            .next()
            .expect("the tuned ragdoll has a rod");
        self.psi.push(state.psi);
        self.tau.push(state.tau);
        self.energy
            .push(world.kinetic_energy() + world.potential_energy());
        let residual = crate::metrics::ragdoll_residual(world, &lab.ragdolls[0]);
        self.dislocation_cm.push(residual.dislocation_cm);
    }
}

/// A series' settled value: its mean over the last `window` samples.
pub fn settled(series: &[f32], window: usize) -> f32 {
    let tail = &series[series.len().saturating_sub(window.max(1))..];
    tail.iter().sum::<f32>() / tail.len().max(1) as f32
}

/// Time (s) from which `series` stays within [`SETTLING_BAND`] of `target` (of its largest
/// magnitude where `target` is about zero; at least 1e-4); infinity if it is still outside at
/// the end.
pub fn settling_time(series: &[f32], target: f32, dt: f32) -> f32 {
    let peak = series.iter().fold(0.0f32, |m, x| m.max(x.abs()));
    let scale = if target.abs() > 1e-3 * peak.max(1e-9) {
        target.abs()
    } else {
        peak
    };
    // 1e-4 rad: a series that hardly moves has settled
    let band = (SETTLING_BAND * scale).max(1e-4);
    match series.iter().rposition(|x| (x - target).abs() > band) {
        None => 0.0,
        Some(i) if i + 1 == series.len() => f32::INFINITY,
        Some(i) => (i + 1) as f32 * dt,
    }
}

/// A copy's row of the summary.
#[derive(Clone, Debug, PartialEq)]
pub struct TuneRow {
    /// The copy this row sums up.
    pub copy: Copy,
    /// Substeps per frame (the scene's).
    pub substeps: u32,
    /// Settled bend psi (rad): the mean over the last [`SETTLED_WINDOW_S`].
    pub final_psi: f32,
    /// Settled twist tau (rad): the mean over the last [`SETTLED_WINDOW_S`].
    pub final_tau: f32,
    /// Largest psi above the final one (rad).
    pub psi_overshoot: f32,
    /// Time (s) from which psi stays within [`SETTLING_BAND`] of its settled value; infinite if
    /// never.
    pub psi_settling_s: f32,
    /// Time (s) from which tau stays within [`SETTLING_BAND`] of its settled value; infinite if
    /// never.
    pub tau_settling_s: f32,
    /// Mean over the frames of the ragdoll's summed dislocation (cm).
    pub mean_dislocation_cm: f32,
    /// Why the copy stopped, with the frame, if it failed.
    pub failed: Option<String>,
}

fn summarize(copy: &Copy, trace: &Trace, dt: f32, substeps: u32) -> TuneRow {
    let window = (SETTLED_WINDOW_S / dt).round() as usize;
    let final_psi = settled(&trace.psi, window);
    let final_tau = settled(&trace.tau, window);
    let peak = trace.psi.iter().copied().fold(f32::NEG_INFINITY, f32::max);
    let n = trace.dislocation_cm.len().max(1) as f32;
    TuneRow {
        copy: copy.clone(),
        substeps,
        final_psi,
        final_tau,
        psi_overshoot: (peak - final_psi).max(0.0),
        psi_settling_s: settling_time(&trace.psi, final_psi, dt),
        tau_settling_s: settling_time(&trace.tau, final_tau, dt),
        mean_dislocation_cm: trace.dislocation_cm.iter().sum::<f32>() / n,
        failed: trace.failed.clone(),
    }
}

/// Each frame of [`run_grid`]: the frame number, and every running copy's lab (`None` once a
/// copy has failed).
pub type FrameObserver<'a> = dyn FnMut(u64, &[Option<&Lab>]) -> anyhow::Result<()> + 'a;

/// Builds this shard's copies and steps them in lockstep (in parallel across copies), calling
/// `observer` after the initial state and every frame. A copy that fails stops there, and its
/// row says why; the others go on.
pub fn run_grid(
    scene: &Scene,
    config: &TuneConfig,
    observer: &mut FrameObserver<'_>,
) -> anyhow::Result<(Vec<TuneRow>, Vec<Trace>)> {
    let mine: Vec<Copy> = copies(config, scene.def.iterations)
        .into_iter()
        .filter(|c| config.shard.takes(c.index))
        .collect();
    let mut labs = Vec::with_capacity(mine.len());
    for copy in &mine {
        let setting = RodSetting {
            bend: copy.bend,
            twist: copy.twist,
            bend_damping: config.bend_damping,
            twist_damping: config.twist_damping,
        };
        labs.push(build_copy(
            scene,
            setting,
            copy.iterations,
            config.frames,
            copy.offset,
            config.twist_push,
        )?);
    }
    let frames = config.frames.unwrap_or(scene.def.frames);
    let mut traces = vec![Trace::default(); mine.len()];
    let observe = |labs: &[Lab], traces: &[Trace], frame: u64, observer: &mut FrameObserver<'_>| {
        let running: Vec<Option<&Lab>> = (labs.iter().zip(traces))
            .map(|(lab, trace)| trace.failed.is_none().then_some(lab))
            .collect();
        observer(frame, &running)
    };
    observe(&labs, &traces, 0, observer)?;
    for frame in 1..=frames as u64 {
        labs.par_iter_mut()
            .zip(traces.par_iter_mut())
            .filter(|(_, trace)| trace.failed.is_none())
            .for_each(|(lab, trace)| match lab.step() {
                Ok(()) => trace.record(lab),
                Err(e) => trace.failed = Some(format!("frame {frame}: {e}")),
            });
        observe(&labs, &traces, frame, observer)?;
    }
    let (dt, substeps) = (scene.def.dt, scene.def.substeps);
    let rows = (mine.iter().zip(&traces))
        .map(|(copy, trace)| summarize(copy, trace, dt, substeps))
        .collect();
    Ok((rows, traces))
}

/// Column names of [`to_csv`].
pub const CSV_HEADER: &str = "index,bend_kind,bend,twist_kind,twist,iterations,substeps,\
final_psi_rad,final_tau_rad,psi_overshoot_rad,psi_settling_s,tau_settling_s,mean_dislocation_cm,failed";

/// The summary as CSV, one row per copy (the failure message quoted where it needs it).
pub fn to_csv(rows: &[TuneRow]) -> String {
    crate::csv_table::to_text(
        CSV_HEADER,
        rows.iter().map(|r| {
            let (bend_kind, bend) = r.copy.bend.columns();
            let (twist_kind, twist) = r.copy.twist.columns();
            vec![
                r.copy.index.to_string(),
                bend_kind.to_string(),
                bend.to_string(),
                twist_kind.to_string(),
                twist.to_string(),
                r.copy.iterations.to_string(),
                r.substeps.to_string(),
                format!("{:.5}", r.final_psi),
                format!("{:.5}", r.final_tau),
                format!("{:.5}", r.psi_overshoot),
                format!("{:.3}", r.psi_settling_s),
                format!("{:.3}", r.tau_settling_s),
                format!("{:.5}", r.mean_dislocation_cm),
                r.failed.clone().unwrap_or_default(),
            ]
        }),
    )
}

/// The summary chart: the settled bend against the bend setting, one line per twist setting
/// and iteration count (log x axis when every setting is positive).
pub fn chart(scene: &str, rows: &[TuneRow]) -> Chart {
    let mut series: Vec<Series> = Vec::new();
    for r in rows.iter().filter(|r| r.failed.is_none()) {
        let label = format!("{}, {} it", r.copy.twist.label("twist"), r.copy.iterations);
        let x = r.copy.bend.columns().1 as f64;
        let point = (x, r.final_psi as f64);
        match series.iter_mut().find(|s| s.label == label) {
            Some(s) => s.points.push(point),
            None => series.push(Series {
                label,
                points: vec![point],
            }),
        }
    }
    for s in &mut series {
        s.points.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    let setting = rows.first().map_or(Softness::Alpha(0.0), |r| r.copy.bend);
    let x_label = match setting {
        Softness::Alpha(_) => "alpha_b (fraction of psi removed per iteration)",
        Softness::Stiffness(_) => "bend stiffness (N m/rad)",
    };
    Chart {
        title: format!("{scene}: the bend each setting ends at"),
        x_label: x_label.into(),
        y_label: format!("psi, mean of the last {SETTLED_WINDOW_S} s (rad)"),
        x_log: rows.iter().all(|r| r.copy.bend.columns().1 > 0.0),
        y_log: false,
        series,
    }
}

/// The settled psi of the tuned ragdoll with `setting` at `iterations` (no push: the scene's
/// own motion), over the scene's frames or `frames`; `None` if it has not settled
/// ([`settled_value`]).
pub fn settled_psi(
    scene: &Scene,
    setting: RodSetting,
    iterations: u32,
    frames: Option<u32>,
) -> anyhow::Result<Option<f32>> {
    let mut lab = build_copy(scene, setting, iterations, frames, Vec3::ZERO, 0.0)?;
    let frames = frames.unwrap_or(scene.def.frames);
    let mut trace = Trace::default();
    for frame in 1..=frames {
        lab.step()
            .with_context(|| format!("settling at frame {frame}"))?;
        trace.record(&lab);
    }
    Ok(settled_value(&trace.psi, scene.def.dt))
}

/// The mean of `series` over the last [`SETTLED_WINDOW_S`], if it stays within
/// [`SETTLED_BAND`] of it there (or within [`SETTLED_BAND_RAD`], for small values).
pub fn settled_value(series: &[f32], dt: f32) -> Option<f32> {
    let window = ((SETTLED_WINDOW_S / dt).round() as usize).clamp(1, series.len().max(1));
    let value = settled(series, window);
    let band = (SETTLED_BAND * value.abs()).max(SETTLED_BAND_RAD);
    let tail = &series[series.len() - window..];
    tail.iter()
        .all(|x| (x - value).abs() <= band)
        .then_some(value)
}

/// Which setting [`match_psi`] bisects.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MatchBy {
    /// The relaxation alpha_b (eq. 11).
    AlphaBend,
    /// The bend stiffness (N m/rad), critically damped.
    BendStiffness,
}

/// The upper body's moment of inertia about the rod's first end (kg m^2): the bodies above it,
/// as points plus their own inertia. What the matching's damping is scaled by.
fn bend_inertia(lab: &Lab) -> f32 {
    let world = &lab.world;
    let base = world.constraints.iter().find_map(|c| match c {
        Constraint::Rod(rod) => Some(world.body(rod.body_a).position),
        _ => None,
    });
    let Some(base) = base else { return 0.0 };
    (world.bodies.iter())
        .filter(|b| b.is_dynamic() && b.position.y > base.y)
        .map(|b| b.mass * (b.position - base).length_squared() + b.inertia.max_element())
        .sum()
}

/// The upper body's inertia about the rod's base in the scene (what [`matching_setting`]
/// damps by).
pub fn matching_inertia(scene: &Scene, twist: Softness, iterations: u32) -> anyhow::Result<f32> {
    let plain = matching_setting(MatchBy::AlphaBend, 0.0, twist, 0.0);
    Ok(bend_inertia(&build_copy(
        scene,
        plain,
        iterations,
        None,
        Vec3::ZERO,
        0.0,
    )?))
}

/// The rod setting [`match_psi`] runs for a bend `value`: stiffness critically damped,
/// `c = 2 sqrt(k I)`, with `I` from [`matching_inertia`].
pub fn matching_setting(by: MatchBy, value: f32, twist: Softness, inertia: f32) -> RodSetting {
    let (bend, bend_damping) = match by {
        MatchBy::AlphaBend => (Softness::Alpha(value), None),
        MatchBy::BendStiffness => (
            Softness::Stiffness(value),
            Some(2.0 * (value * inertia).sqrt()),
        ),
    };
    RodSetting {
        bend,
        twist,
        bend_damping,
        twist_damping: None,
    }
}

/// The bend setting whose settled psi is within `tolerance` of `target`: scanned over
/// alpha_b in [1e-6, 1] or the stiffness in [0.1, 1e5] N m/rad (log spaced), then bisected (in
/// log space) between the stiffest neighbours that bracket it. Stiffness runs are
/// critically damped (`c = 2 sqrt(k I)`, `I` the upper body's inertia about the rod's base;
/// damping does not move where they settle) and every run lasts twice the scene's frames.
/// `None` if no setting reaches the target. The twist stays `twist`.
pub fn match_psi(
    scene: &Scene,
    target: f32,
    by: MatchBy,
    twist: Softness,
    iterations: u32,
    tolerance: f32,
) -> anyhow::Result<Option<(f32, f32)>> {
    let frames = Some(matching_frames(scene));
    let inertia = matching_inertia(scene, twist, iterations)?;
    let setting = |value: f32| matching_setting(by, value, twist, inertia);
    // a run still moving at the end counts as no value (NaN)
    let psi_at = |value: f32| {
        settled_psi(scene, setting(value), iterations, frames).map(|p| p.unwrap_or(f32::NAN))
    };
    let (lo, hi) = match by {
        MatchBy::AlphaBend => (1e-6f32, 1.0f32),
        MatchBy::BendStiffness => (0.1, 1e5),
    };
    // A coarse scan first: psi need not fall monotonically as the setting rises (a weak rod
    // swings or tips over), so bisect in the stiffest pair of neighbours that brackets it.
    let scan: Vec<f32> = (0..=MATCH_SCAN)
        .map(|i| lo * (hi / lo).powf(i as f32 / MATCH_SCAN as f32))
        .collect();
    let psis = (scan.par_iter())
        .map(|&v| psi_at(v))
        .collect::<anyhow::Result<Vec<f32>>>()?;
    let within = |psi: f32| (psi - target).abs() <= tolerance;
    // the runs that settled, in the order of the setting
    let settled: Vec<(f32, f32)> = (scan.iter().zip(&psis))
        .filter(|(_, psi)| psi.is_finite())
        .map(|(&v, &psi)| (v, psi))
        .collect();
    if let Some(&found) = settled.iter().rev().find(|(_, psi)| within(*psi)) {
        return Ok(Some(found));
    }
    let Some(pair) = (settled.windows(2).rev()).find(|w| w[0].1 > target && w[1].1 < target) else {
        return Ok(None);
    };
    let ((mut lo, _), (mut hi, psi_hi)) = (pair[0], pair[1]);
    let mut best = (hi, psi_hi);
    for _ in 0..40 {
        let mid = (lo * hi).sqrt();
        let psi = psi_at(mid)?;
        if (psi - target).abs() < (best.1 - target).abs() {
            best = (mid, psi);
        }
        if within(psi) {
            break;
        }
        // an unsettled run (NaN) is on the soft side
        if psi > target || psi.is_nan() {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(within(best.1).then_some(best))
}

/// Settings [`match_psi`] scans before it bisects, minus one.
const MATCH_SCAN: usize = 12;

/// Frames of every run [`match_psi`] makes: twice the scene's, and at least
/// [`MATCHING_SECONDS`] (the paper's alpha settles slowly: 20 s and more to within 2% in
/// passive bending).
pub fn matching_frames(scene: &Scene) -> u32 {
    (2 * scene.def.frames).max((MATCHING_SECONDS / scene.def.dt).ceil() as u32)
}

/// Shortest run [`match_psi`] makes (s).
pub const MATCHING_SECONDS: f32 = 30.0;

/// How close a match must land (rad): 0.002 rad, or 1% of a smaller target.
pub fn match_tolerance(target: f32) -> f32 {
    (0.01 * target.abs()).clamp(1e-4, 0.002)
}

/// The settled bend of the scene's chain3 spine (its first chain3 ragdoll, else the tuned one
/// with the chain3 spine), measured as the rod would: the angle between the pelvis's and the
/// chest's tangents, the rod's frames taken at the start; `None` if it does not settle.
pub fn chain3_psi(scene: &Scene, iterations: u32) -> anyhow::Result<Option<f32>> {
    let mut scene = scene.clone();
    let def = &mut scene.def;
    let mut ragdoll = match def.ragdoll.iter().find(|r| r.spine == SpineKind::Chain3) {
        Some(r) => r.clone(),
        None => tuned_ragdoll(&scene)?,
    };
    ragdoll.spine = SpineKind::Chain3;
    let name = ragdoll.name.clone();
    scene.def.ragdoll = vec![ragdoll];
    scene.def.iterations = iterations;
    let mut lab = scene.build()?;
    let find = |part: &str| {
        (lab.world.find_body(&format!("{name}/{part}")))
            .with_context(|| format!("the chain3 ragdoll has no {part}"))
    };
    let (pelvis, chest) = (find("pelvis")?, find("chest")?);
    let probe =
        crate::constraint::Rod::instantiate("probe", &lab.world.bodies, pelvis, chest, Vec3::Z)
            .map_err(anyhow::Error::msg)?;
    let mut psi = Vec::new();
    for _ in 0..scene.def.frames {
        lab.step()?;
        psi.push(
            probe
                .state(lab.world.body(pelvis), lab.world.body(chest))
                .psi,
        );
    }
    Ok(settled_value(&psi, scene.def.dt))
}
