//! The stability suite: where methods fail.
//!
//! A fixed list of short scenes ([`suite`]), each run once per [`Method`] through
//! [`sim::run`] ([`run_case`], with the caller's observer so the run can be recorded); every
//! run gets a [`Verdict`], stable, jittering or exploded, from measured criteria ([`verdict`],
//! a pure function of the [`Measures`]; thresholds in [`Criteria::default`]). The whole suite
//! (16 cases, 62 runs) takes about a second in release.
//!
//! # Methods
//!
//! | method | ragdoll spine | ball-and-sockets | chains |
//! |---|---|---|---|
//! | `chain3-cheap` | three joints | cheap (one row along the error) | ball-and-socket chain, cheap |
//! | `chain3-exact` | three joints | exact (3x3 block) | ball-and-socket chain, exact |
//! | `rod` | one rod (paper §5) | exact | a chain of rods of the same length |
//! | `single` | one joint | exact | does not apply (`-`) |
//!
//! The rod and single spines use exact limb joints, so they differ from `chain3-exact` in the
//! spine alone. Spine stiffness is the passive bending scene's pair, which makes both spines
//! slump about as far: spine springs of relaxation 0.1 (chain3, single); alpha_b = 0.005,
//! alpha_t = 0.5 (rod). The stiff cases use springs of relaxation 1 (hard angular targets) and
//! alpha_b = alpha_t = 1.
//!
//! # Cases
//!
//! 60 Hz and 20 iterations unless the name says otherwise; 4 s (3 s for the last three).
//!
//! | case | what |
//! |---|---|
//! | `baseline` | passive bending (Fig. 2): pelvis fixed, upper body tilted 8 deg, slumping |
//! | `dt_1_30`, `dt_1_15` | the same at long time steps |
//! | `iterations_2`, `iterations_1` | the same with 2 and 1 iterations |
//! | `heavy_hand_100`, `_1000` | pelvis fixed, a sphere of 100 (1000) forearm masses held in the left hand, the load through the spine |
//! | `light_forearms_100`, `_1000` | passive bending with both forearms 100 (1000) times lighter |
//! | `chain_40` | 40 capsule links (4 m, 1 kg each) released from horizontal; rod: 40 rods between the link centres, alpha_b = 0 (bending free like the joints) |
//! | `chain_40_stretched` | the same hanging, each link 5 cm from its joint (2 m of error in all) |
//! | `stiff_spine_dt_1_30`, `_1_15` | upper body tilted 30 deg, held by a stiff spine, at long time steps (the paper: stiff rods stay stable) |
//! | `projectile_50` | contacts on: a 20 kg sphere at 50 m/s into a standing ragdoll's chest |
//! | `bent_near_pi` | pelvis fixed, spine bent 175 deg (rod psi near pi; the joint spines only reach their 74 deg limit), springs resting straight |
//! | `hanging_near_zero` | hung by the head, spine bent 1e-3 rad (rod psi swinging through 0) |
//!
//! # Measures and criteria
//!
//! Speeds are of a body's fastest surface point ([`crate::body::Body::max_point_speed`]);
//! energies are kinetic plus gravitational; "the last second" is the last second of frames.
//! See [`Measures`] for the exact definitions. A run is, checking in this order:
//!
//! - **exploded** if the world's health check stopped it (NaN, or a body past the speed bounds
//!   of [`crate::world::Settings`]: 250 m/s, 500 rad/s), or any measure is NaN, or
//!   - the energy it holds over the last second exceeds its start by more than **1.0** energy
//!     scale (`KE_0 + M g (1 m)`, lifting the whole scene a metre): created and kept; or
//!   - a peak speed above **5x** the scene's speed reference (its fastest start speed plus a
//!     fall across its extent plus a metre): a whipped chain's end reaches 1.7x, a ragdoll
//!     flailing under a 167 kg weight 3.5x, one torn by a 1.67 t weight 12x to 31x; or
//!   - torn: a joint more than **50 cm** apart over the last second (the 1.67 t weight: 90 to
//!     122 cm; nothing else passes 5 cm);
//! - **jittering** if
//!   - the energy held over the last second exceeds its start by more than **0.1**; or
//!   - the energy at any moment exceeds its start by more than **0.5** (a pop: smooth runs
//!     stay below 0.2, 1-iteration chain3 spines pop 0.5 to 0.7, a pre-stretched chain 1.6 to
//!     2.5); or
//!   - a joint more than **5 cm** apart over the last second (visibly open; the stable runs
//!     stay below 2.5 cm); or
//!   - in a scene that should come to rest (the hanging ones), the fastest point moves faster
//!     than **0.2 m/s** over the last second (calm hanging ragdolls: below 0.05 m/s); or
//!   - shake above **0.1 m/s** (stable-looking runs measure up to 0.07, visibly twitching ones
//!     0.15 and more: a 1-iteration arm twisting back and forth, chain3 spines at dt = 1/15);
//! - **stable** otherwise.
//!
//! Energy a scene may gain legitimately is subtracted first (its energy allowance): the
//! potential energy hidden by a pre-stretched chain's errors, or taken by a bend its springs
//! will undo.
//!
//! # Tables
//!
//! [`table_markdown`]: rows are cases, columns methods, cells the verdict and its key number
//! (the criterion that tripped, or the mean residual of a stable run). [`table_csv`]: one row
//! per run with the columns of [`CSV_HEADER`]:
//!
//! | column | meaning |
//! |---|---|
//! | `case`, `method`, `verdict` | names as displayed |
//! | `frames_run`, `frames` | frames stepped before any failure, frames asked for |
//! | `energy_growth`, `final_energy_growth` | peak and last-second energy rise over the energy scale |
//! | `peak_speed_m_s`, `speed_reference_m_s` | fastest point over the run, the scene's reference |
//! | `final_speed_m_s` | fastest point, mean over the last second |
//! | `settles` | whether the scene should come to rest |
//! | `max_residual_cm`, `mean_residual_cm` | largest joint dislocation: maximum, last-second mean |
//! | `mean_angular_rad` | largest angular violation, last-second mean (not a criterion) |
//! | `shake_m_s` | shake, last-second mean |
//! | `failed` | the health check's message, quoted where it holds a comma; empty if none |
//!
//! [`sim::run`]: crate::sim::run

mod criteria;
mod run;
mod scenarios;
mod table;

pub use criteria::{tripped, verdict, Criteria};
pub use run::{run_case, run_suite};
pub use scenarios::{suite, Built, Case, Scenario, FOREARM_MASS};
pub use table::{table_csv, table_markdown, CSV_HEADER};

/// How the ragdoll's spine (or a chain) is built.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// Three-joint spine, cheap ball-and-sockets everywhere (one row along the error).
    Chain3Cheap,
    /// Three-joint spine, exact (3x3 block) ball-and-sockets everywhere.
    Chain3Exact,
    /// Rod spine (paper §5), exact limb joints.
    Rod,
    /// One ball-and-socket spine, exact joints.
    Single,
}

impl Method {
    /// Every method, in table column order.
    pub const ALL: [Method; 4] = [
        Method::Chain3Cheap,
        Method::Chain3Exact,
        Method::Rod,
        Method::Single,
    ];
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Method::Chain3Cheap => "chain3-cheap",
            Method::Chain3Exact => "chain3-exact",
            Method::Rod => "rod",
            Method::Single => "single",
        })
    }
}

/// A run's outcome, worst last (see the module docs for the criteria).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Verdict {
    /// None of the criteria tripped.
    Stable,
    /// Energy gained, a pop, a joint visibly open, motion that does not settle, or shaking.
    Jittering,
    /// Stopped by the health check, a NaN, energy created and kept, a runaway speed, or torn.
    Exploded,
}

impl std::fmt::Display for Verdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Verdict::Stable => "stable",
            Verdict::Jittering => "jittering",
            Verdict::Exploded => "exploded",
        })
    }
}

/// What one run measured. Speeds are of a body's fastest surface point
/// ([`crate::body::Body::max_point_speed`]); "the last second" is the last second of frames run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Measures {
    /// Frames stepped without failure, and the frames asked for.
    pub frames_run: u32,
    /// Frames asked for.
    pub frames: u32,
    /// Largest rise of the total mechanical energy (kinetic + potential) above its start,
    /// less the scene's energy allowance, over the energy scale `KE_0 + M g (1 m)` (M: the
    /// dynamic mass): 1 is the energy of lifting the whole scene a metre. Zero when it only
    /// falls.
    pub energy_growth: f32,
    /// The same rise, mean over the last second: energy the solver created and kept.
    pub final_energy_growth: f32,
    /// Fastest point of any dynamic body over the run, the failing frame included (m/s), and
    /// the speed the scene can reach by itself: its fastest start speed plus the speed of a
    /// fall across the box holding its body centres plus a metre.
    pub peak_speed: f32,
    /// The scene's own reachable speed (m/s); `peak_speed` is judged against it.
    pub speed_reference: f32,
    /// Fastest point of any dynamic body, mean over the last second (m/s).
    pub final_speed: f32,
    /// Whether the scene should be at rest by the end (then `final_speed` must be small).
    pub settles: bool,
    /// Largest dislocation of any constraint (cm): its maximum over the run, and its mean over
    /// the last second.
    pub max_residual_cm: f32,
    /// Largest dislocation of any constraint (cm), mean over the last second.
    pub mean_residual_cm: f32,
    /// Largest angular violation of any constraint (rad), mean over the last second.
    pub mean_angular_rad: f32,
    /// Frame-to-frame shaking (m/s), mean over the last second: for each body, how far its
    /// velocity at a frame lies from the mean of the frames before and after, the largest over
    /// bodies. The velocity is the linear one plus the angular one scaled to the speed it gives
    /// the body's surface (as [`crate::body::Body::max_point_speed`]: a capsule's spin about
    /// its axis by its radius, about the other axes by its half-length). Smooth motion gives a
    /// value second order in dt; a body whose velocity flips every frame gives its speed.
    pub shake: f32,
    /// The NaN or explosion message of the world's health check, if the run stopped.
    pub failed: Option<String>,
}

/// One run of the suite: a case, a method and its verdict.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// The case's name.
    pub case: &'static str,
    /// The spine method it ran.
    pub method: Method,
    /// Stable, jittering or exploded.
    pub verdict: Verdict,
    /// What the run measured.
    pub measures: Measures,
}
