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

use crate::constraint::Constraint;
use crate::lab::Lab;
use crate::math::Vec3;
use crate::ragdoll::SpineKind;
use crate::scene::{RagdollDef, Scene};
pub use crate::shard::Shard;

mod grid;
mod matching;

pub use grid::{chart, run_grid, to_csv, FrameObserver, TuneRow, CSV_HEADER};
pub use matching::{
    chain3_psi, match_psi, match_tolerance, matching_frames, matching_inertia, matching_setting,
    settled_psi, settled_value, MatchBy, MATCHING_SECONDS,
};

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
