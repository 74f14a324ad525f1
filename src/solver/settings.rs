//! The simulation settings ([`Settings`]), how a colour's rows are solved ([`SolverKind`]),
//! and the defaults of the health bounds.

use super::declared::{choice_setting, Declaration, SettingValue};
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
/// found afresh, against 2.5-4.2 cm when each substep detects; `docs/landings.md`). It costs N
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

/// Calls `$then! { { ARGS } SETTINGS }` with every method setting, each declared once here:
/// its doc, type, default (the paper's method), unit, bounds and chart label (`{}` for the
/// value; empty: never named). The solver's [`Settings`], the scene file's keys, a
/// `[[variant]]`'s and a named method's fields, the command line's flags, the sweep's
/// dimensions and `rodlab settings` are all derived from this list, so adding a setting
/// touches this declaration and the code that uses it.
///
/// The order is the order of `rodlab settings`, of a chart label's parts and of the sweep's
/// dimensions (the last, `iterations`, innermost).
macro_rules! method_settings {
    ($then:ident ! { $($args:tt)* }) => {
        $then! {
            { $($args)* }
            /// How the rows of a colour are solved: scalar, one row after another (the
            /// reference), or simd, W rows at once in SIMD lanes, branch-free (paper §7), the
            /// same maths.
            solver: $crate::solver::SolverKind = $crate::solver::SolverKind::Scalar,
                unit "", bounds $crate::solver::Bounds::Any, label "{}";
            /// Substeps per frame, each of `dt / substeps` with `iterations` sweeps (Macklin et
            /// al. 2019, "Small Steps in Physics Simulation"); 1 is the paper's method.
            substeps: u32 = 1,
                unit "", bounds $crate::solver::Bounds::Count { min: 1, max: $crate::solver::MAX_SUBSTEPS },
                label "x{}";
            /// When contact points are found: once a `frame` (the paper's method), or afresh at
            /// every `substep` (points found again keep their impulses and friction anchors).
            contact_detection: $crate::solver::ContactDetection = $crate::solver::ContactDetection::Frame,
                unit "", bounds $crate::solver::Bounds::Any, label "redetect";
            /// Each substep starts every contact point with this fraction of the normal impulse
            /// it ended the last substep with (warm starting, Rapier's
            /// `warmstart_coefficient`); 0 is the paper's method.
            contact_warm_start: f32 = 0.0,
                unit "", bounds $crate::solver::Bounds::from_to(0.0, 1.0), label "warm{}";
            /// Soft contacts: each point a damped spring of this natural frequency (see
            /// `contact::Softness`); 0 is the paper's hard projection.
            contact_hertz: f32 = 0.0,
                unit "Hz", bounds $crate::solver::Bounds::at_least(0.0), label "soft{}Hz";
            /// The soft contacts' damping ratio (1: critical).
            contact_damping_ratio: f32 = 1.0,
                unit "", bounds $crate::solver::Bounds::at_least(0.0), label "zeta{}";
            /// Stacking: in a contact the lower body counts `e^(k dh)` times heavier, `dh` the
            /// other's height above it (see `contact::Stacking`); 0 is the paper's contact.
            contact_stacking: f32 = 0.0,
                unit "1/m", bounds $crate::solver::Bounds::from_to(0.0, $crate::solver::MAX_CONTACT_STACKING),
                label "stack{}";
            /// The most times heavier stacking makes the lower body (`e^(k dh)` capped); inf is
            /// no cap.
            contact_stacking_max_ratio: f32 = f32::INFINITY,
                unit "", bounds $crate::solver::Bounds::Number { min: 1.0, min_included: true, max: f32::INFINITY },
                label "<={}";
            /// Deep overlap is pushed out no faster than this (Box2D's `maxContactPushSpeed`);
            /// inf pushes it out at once, the paper-era projection.
            contact_push_speed: f32 = f32::INFINITY,
                unit "m/s", bounds $crate::solver::Bounds::positive_or_inf(), label "push{}";
            /// Contact-only sweeps after each substep's iterations (PhysX's and Jolt's extra
            /// position iterations, for contacts alone); 0 is the paper's method.
            contact_extra_sweeps: u32 = 0,
                unit "", bounds $crate::solver::Bounds::Count { min: 0, max: $crate::solver::MAX_ITERATIONS },
                label "sweeps{}";
            /// Joint damping: a rotational dashpot across every ball-and-socket joint and rod,
            /// the torque `-k w_rel` (see `constraint::damper`); 0 is the paper's method (no
            /// damper rows at all).
            joint_damping: f32 = 0.0,
                unit "N m s/rad", bounds $crate::solver::Bounds::at_least(0.0), label "jd{}";
            /// Joint friction: the most torque with which every ball-and-socket joint and rod
            /// resists a relative turn, Coulomb's (see `constraint::damper`); 0 is the paper's
            /// method.
            joint_friction: f32 = 0.0,
                unit "N m", bounds $crate::solver::Bounds::at_least(0.0), label "jf{}";
            /// Each substep, a faster body's angular velocity is scaled down to this speed
            /// before it moves (Jolt's `mMaxAngularVelocity`, PhysX's `maxAngularVelocity`); inf
            /// is the paper's method: no limit.
            angular_speed_limit: f32 = f32::INFINITY,
                unit "rad/s", bounds $crate::solver::Bounds::positive_or_inf(), label "spin<={}";
            /// Islands of bodies that stay still fall asleep and leave the step (see `sleep`);
            /// off in the paper's scenes, whose residuals are measured every frame.
            sleep: bool = false,
                unit "", bounds $crate::solver::Bounds::Any, label "sleep";
            /// Frame time step.
            dt: f32 = 1.0 / 60.0,
                unit "s", bounds $crate::solver::Bounds::Number { min: 0.0, min_included: false, max: $crate::solver::MAX_DT },
                label "";
            /// Solver iterations per substep (paper §8: a fixed number).
            iterations: u32 = 20,
                unit "", bounds $crate::solver::Bounds::Count { min: 1, max: $crate::solver::MAX_ITERATIONS },
                label "";
        }
    };
}
pub(crate) use method_settings;

/// Defines [`Settings`] from the method settings and the world's own.
macro_rules! settings_struct {
    ({} $( $(#[doc = $doc:literal])* $name:ident : $ty:ty = $default:expr,
        unit $unit:literal, bounds $bounds:expr, label $label:literal; )*) => {
        /// Simulation settings: the method settings (`method_settings!`, the scene file's
        /// top-level keys, overridable on the command line) and the world's bounds and
        /// constants (the scene file's alone).
        #[derive(Clone, Debug, PartialEq)]
        pub struct Settings {
            $( $(#[doc = $doc])* pub $name: $ty, )*
            /// Gravitational acceleration (m/s^2).
            pub gravity: Vec3,
            /// A dynamic body faster than this (m/s) counts as exploded.
            pub max_linear_speed: f32,
            /// A dynamic body spinning faster than this (rad/s) counts as exploded.
            pub max_angular_speed: f32,
            /// A joint or rod whose hard constraints are further apart than this (m) after a
            /// frame counts as broken apart.
            pub max_separation: f32,
            /// A contact deeper than this (m) after a frame counts as a body driven through
            /// another.
            pub max_penetration: f32,
            /// Whether bodies collide. Off, the step does no collision work at all.
            pub contacts: bool,
            /// Contact points are made this far (m) before the surfaces touch.
            pub contact_margin: f32,
            /// Velocity damping rate (1/s): each substep `v /= 1 + h c`. Zero (the default) in
            /// the paper's scenes.
            pub linear_damping: f32,
            /// Angular velocity damping rate (1/s): each substep `w /= 1 + h c`.
            pub angular_damping: f32,
        }

        impl Default for Settings {
            fn default() -> Self {
                Settings {
                    $( $name: $default, )*
                    gravity: Vec3::new(0.0, -9.81, 0.0),
                    max_linear_speed: DEFAULT_MAX_LINEAR_SPEED,
                    max_angular_speed: DEFAULT_MAX_ANGULAR_SPEED,
                    max_separation: DEFAULT_MAX_SEPARATION,
                    max_penetration: DEFAULT_MAX_PENETRATION,
                    contacts: false,
                    contact_margin: 0.02,
                    linear_damping: 0.0,
                    angular_damping: 0.0,
                }
            }
        }

        /// Every method setting's declaration, in the declared order.
        pub const METHOD_SETTINGS: &[Declaration] = &[$(
            Declaration {
                name: stringify!($name),
                doc: concat!($($doc, "\n",)*),
                unit: $unit,
                bounds: $bounds,
                values: || <$ty as SettingValue>::values(&$bounds, $unit),
                label: $label,
            },
        )*];

        impl Settings {
            /// Each method setting's value as text, in the declared order (for labels and
            /// tables).
            pub fn method_texts(&self) -> Vec<(&'static str, String)> {
                vec![$( (stringify!($name), self.$name.to_string()), )*]
            }

            /// Sets the method setting `key` from its text (as [`Settings::method_texts`] and
            /// the command line write it), within its bounds.
            pub fn set_method_text(&mut self, key: &str, text: &str) -> Result<(), String> {
                $( if key == stringify!($name) {
                    self.$name = <$ty as SettingValue>::parse_text(text)?.checked(&$bounds, $unit)?;
                    return Ok(());
                } )*
                Err(format!("{key:?} is not a method setting"))
            }

            /// The first method setting outside its bounds: its key and what it must be.
            pub fn check_method(&self) -> Result<(), (&'static str, String)> {
                $( SettingValue::checked(self.$name.clone(), &$bounds, $unit)
                    .map_err(|m| (stringify!($name), m))?; )*
                Ok(())
            }
        }
    };
}
method_settings!(settings_struct! {});

choice_setting!(SolverKind: "scalar, simd", ContactDetection: "frame, substep");

/// Iterations per substep, at most (and contact-only sweeps).
pub const MAX_ITERATIONS: u32 = 10_000;
/// Substeps per frame, at most.
pub const MAX_SUBSTEPS: u32 = 1_000;
/// The longest time step (s).
pub const MAX_DT: f32 = 1.0;
/// The largest stacking rate (1/m): at 1000 a body 1 cm lower already counts 22 000 times
/// heavier.
pub const MAX_CONTACT_STACKING: f32 = 1000.0;

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
