//! The simulation settings ([`Settings`]), how a colour's rows are solved ([`SolverKind`]),
//! and the defaults of the health bounds.

use crate::math::Vec3;

/// How the rows of a colour are solved.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SolverKind {
    /// One row after another: the reference.
    #[default]
    Scalar,
    /// W rows at once in SIMD lanes, branch-free (paper §7); the same maths.
    Simd,
}

impl std::fmt::Display for SolverKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SolverKind::Scalar => "scalar",
            SolverKind::Simd => "simd",
        })
    }
}

/// When contact points are found: once a frame (the paper's method and the reference), or
/// afresh at the start of every substep.
///
/// A point's normal and body-space surface points are fixed until the next detection. Limbs
/// that slide and roll over each other at 2-5 m/s within a frame carry those points off the
/// features that really touch, so a detection on the frame's final poses finds overlaps the
/// points no longer see (the drop at 4 substeps of 5 iterations over four layouts: 4.7-7.5 cm
/// found afresh, against 2.5-4.2 cm when each substep detects; `docs/solver.md`). It costs N
/// detections a frame instead of one.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ContactDetection {
    /// Once per frame, at the frame's starting poses, with a speculative reach for the frame.
    #[default]
    Frame,
    /// At the start of every substep, with a speculative reach for the substep; points found
    /// again keep their impulses and friction anchors ([`crate::contact::manifold`]).
    Substep,
}

impl std::fmt::Display for ContactDetection {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ContactDetection::Frame => "frame",
            ContactDetection::Substep => "substep",
        })
    }
}

/// Simulation settings (from the scene file, overridable on the command line).
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Gravitational acceleration (m/s^2).
    pub gravity: Vec3,
    /// Frame time step (s).
    pub dt: f32,
    /// Solver iterations per substep (paper §8: a fixed number).
    pub iterations: u32,
    /// Substeps per frame, each of `dt / substeps` with `iterations` sweeps (Macklin et al.
    /// 2019). 1 is the paper's method and the reference.
    pub substeps: u32,
    /// How the rows of a colour are solved: scalar (the reference) or SIMD lanes.
    pub solver: SolverKind,
    /// A dynamic body faster than this (m/s) counts as exploded.
    pub max_linear_speed: f32,
    /// A dynamic body spinning faster than this (rad/s) counts as exploded.
    pub max_angular_speed: f32,
    /// Each substep, a faster body's angular velocity is scaled down to this speed (rad/s)
    /// before it moves: Jolt's `mMaxAngularVelocity`, PhysX's `maxAngularVelocity`, Box2D's
    /// `maxRotation` per step. Infinity (the default) is the paper's method: no limit, and a
    /// spin-up in a pile runs into the explosion bound [`Settings::max_angular_speed`] instead.
    pub angular_speed_limit: f32,
    /// A joint or rod whose hard constraints are further apart than this (m) after a frame
    /// counts as broken apart.
    pub max_separation: f32,
    /// A contact deeper than this (m) after a frame counts as a body driven through another.
    pub max_penetration: f32,
    /// Whether bodies collide. Off, the step does no collision work at all.
    pub contacts: bool,
    /// Contact points are made this far (m) before the surfaces touch.
    pub contact_margin: f32,
    /// When contact points are found: once a frame (the paper's method) or every substep.
    pub contact_detection: ContactDetection,
    /// Deep overlap is pushed out no faster than this (m/s); infinity pushes it out at once.
    pub contact_push_speed: f32,
    /// Contact-only sweeps after each substep's `iterations` (PhysX's and Jolt's extra
    /// position iterations, for contacts alone): they push out the overlap the last joint
    /// sweep left, so the substep ends with its contacts solved most. 0 (the default) is the
    /// paper's method.
    pub contact_extra_sweeps: u32,
    /// Each substep starts every contact point with this fraction of the normal impulse it
    /// ended the last substep with (warm starting; Rapier's `warmstart_coefficient`); a point
    /// found again next frame keeps it ([`crate::contact::manifold`]). 0 is the paper's method.
    pub contact_warm_start: f32,
    /// Soft contacts: natural frequency (Hz) and damping ratio of each contact point
    /// ([`crate::contact::Softness`]). 0 Hz (the default) is the paper's hard projection.
    pub contact_hertz: f32,
    /// Soft contacts' damping ratio zeta (1: critical).
    pub contact_damping_ratio: f32,
    /// Stacking (1/m): in a contact the lower body counts `e^(k dh)` times heavier, `dh` the
    /// other's height above it ([`crate::contact::Stacking`]). 0 (the default) is the paper's
    /// contact.
    pub contact_stacking: f32,
    /// The most times heavier stacking makes the lower body, `e^(k dh)` capped; infinite (the
    /// default) is no cap.
    pub contact_stacking_max_ratio: f32,
    /// Islands of bodies that stay still fall asleep and leave the step ([`crate::sleep`]).
    /// Off (the default) in the paper's scenes, whose residuals are measured every frame.
    pub sleep: bool,
    /// Velocity damping rates (1/s): each substep `v /= 1 + h c`. Zero (the default) in the
    /// paper's scenes; a game scene may use a little to let piles come to rest.
    pub linear_damping: f32,
    /// Angular velocity damping rate (1/s): each substep `w /= 1 + h c`.
    pub angular_damping: f32,
    /// Joint damping (N m s/rad): a rotational dashpot across every ball-and-socket joint and
    /// rod, the torque `-k w_rel` ([`crate::constraint::damper`]), as a ragdoll's muscles would
    /// damp it. Zero (the default) in the paper's scenes: no damper rows at all.
    pub joint_damping: f32,
    /// Joint friction (N m): the most torque with which every ball-and-socket joint and rod
    /// resists a relative turn, Coulomb's ([`crate::constraint::damper`]). Zero (the default) in
    /// the paper's scenes.
    pub joint_friction: f32,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            gravity: Vec3::new(0.0, -9.81, 0.0),
            dt: 1.0 / 60.0,
            iterations: 20,
            substeps: 1,
            solver: SolverKind::Scalar,
            max_linear_speed: DEFAULT_MAX_LINEAR_SPEED,
            max_angular_speed: DEFAULT_MAX_ANGULAR_SPEED,
            angular_speed_limit: f32::INFINITY,
            max_separation: DEFAULT_MAX_SEPARATION,
            max_penetration: DEFAULT_MAX_PENETRATION,
            contacts: false,
            contact_margin: 0.02,
            contact_detection: ContactDetection::Frame,
            contact_push_speed: DEFAULT_CONTACT_PUSH_SPEED,
            contact_extra_sweeps: 0,
            contact_warm_start: 0.0,
            contact_hertz: 0.0,
            contact_damping_ratio: 1.0,
            contact_stacking: 0.0,
            contact_stacking_max_ratio: f32::INFINITY,
            sleep: false,
            linear_damping: 0.0,
            angular_damping: 0.0,
            joint_damping: 0.0,
            joint_friction: 0.0,
        }
    }
}

/// Default limit on the speed at which deep overlap is pushed out (m/s): none, the paper-era
/// projection. Box2D v3 uses 3 m/s; here 3 m/s left a 30-ragdoll pile with a fifth of its bodies
/// still creeping after 10 s (the overlap is pushed out slowly while the velocity pass keeps
/// taking the push's speed away), so the limit waits for the contact work to tune it.
pub const DEFAULT_CONTACT_PUSH_SPEED: f32 = f32::INFINITY;

/// Default explosion bound on linear speed (m/s): well above anything a falling ragdoll or a
/// thrown prop reaches in our scenes (a 50 m/s projectile is the fastest).
pub const DEFAULT_MAX_LINEAR_SPEED: f32 = 250.0;
/// Default explosion bound on angular speed (rad/s), about 80 turns per second.
pub const DEFAULT_MAX_ANGULAR_SPEED: f32 = 500.0;

/// Default bound on a joint's or rod's dislocation after a frame (m): half a metre is no
/// residual error any more but a ragdoll come apart (`--dt 1` left a joint 1 km apart).
pub const DEFAULT_MAX_SEPARATION: f32 = 0.5;

/// Default bound on a contact's depth after a frame (m): deeper than any body here is thick
/// (`--dt 1 --iterations 1` drove bodies 39 m into the floor).
pub const DEFAULT_MAX_PENETRATION: f32 = 0.5;
