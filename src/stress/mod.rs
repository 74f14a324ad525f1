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

mod scenarios;

pub use scenarios::{suite, Built, Case, Scenario, FOREARM_MASS};

use crate::lab::Lab;
use crate::math::Vec3;
use crate::metrics::FrameMetrics;
use crate::shape::Shape;
use crate::sim::{self, Observer};
use crate::world::{SimulationError, World};

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

/// Collects the measures frame by frame and forwards everything to the caller's observer.
struct Probe<'a> {
    inner: &'a mut dyn Observer,
    window: usize,
    allowance: f32,
    initial_energy: f32,
    energy_scale: f32,
    max_energy: f32,
    energies: Vec<f32>,
    peak_speed: f32,
    max_residual_cm: f32,
    /// Per observed frame after the start: fastest point speed, largest dislocation (cm),
    /// largest angular violation (rad), shake (m/s, from the third frame on).
    speeds: Vec<f32>,
    residuals: Vec<f32>,
    angular: Vec<f32>,
    shakes: Vec<f32>,
    /// Per body, (linear, angular x reach) velocities of the last two frames.
    history: [Vec<(Vec3, Vec3)>; 2],
    frames_run: u32,
}

impl<'a> Probe<'a> {
    fn new(inner: &'a mut dyn Observer, window: usize, allowance: f32) -> Self {
        Probe {
            inner,
            window,
            allowance,
            initial_energy: 0.0,
            energy_scale: 1.0,
            max_energy: f32::NEG_INFINITY,
            energies: Vec::new(),
            peak_speed: 0.0,
            max_residual_cm: 0.0,
            speeds: Vec::new(),
            residuals: Vec::new(),
            angular: Vec::new(),
            shakes: Vec::new(),
            history: [Vec::new(), Vec::new()],
            frames_run: 0,
        }
    }

    fn fastest_point(world: &World) -> f32 {
        world
            .bodies
            .iter()
            .filter(|b| b.is_dynamic())
            .map(|b| b.max_point_speed())
            .fold(0.0, nan_max)
    }

    fn velocities(world: &World) -> Vec<(Vec3, Vec3)> {
        world
            .bodies
            .iter()
            .filter(|b| b.is_dynamic())
            .map(|b| (b.linear_velocity, surface_angular_velocity(b)))
            .collect()
    }

    fn observe(&mut self, world: &World, metrics: &FrameMetrics) {
        self.max_energy = nan_max(self.max_energy, metrics.total_energy());
        self.energies.push(metrics.total_energy());
        let speed = Self::fastest_point(world);
        self.peak_speed = nan_max(self.peak_speed, speed);
        self.speeds.push(speed);
        let (mut dislocation, mut angular) = (0.0f32, 0.0f32);
        for constraint in &world.constraints {
            let v = constraint.violation(&world.bodies);
            dislocation = nan_max(dislocation, v.dislocation);
            angular = nan_max(angular, v.angular);
        }
        self.max_residual_cm = nan_max(self.max_residual_cm, 100.0 * dislocation);
        self.residuals.push(100.0 * dislocation);
        self.angular.push(angular);
        let now = Self::velocities(world);
        if self.frames_run >= 2 {
            let shake = self.history[0]
                .iter()
                .zip(&self.history[1])
                .zip(&now)
                .map(|((before, middle), after)| {
                    let linear = middle.0 - 0.5 * (before.0 + after.0);
                    let angular = middle.1 - 0.5 * (before.1 + after.1);
                    (linear.length_squared() + angular.length_squared()).sqrt()
                })
                .fold(0.0, nan_max);
            self.shakes.push(shake);
        }
        self.history.swap(0, 1);
        self.history[1] = now;
    }

    fn measures(&self, frames: u32, settles: bool, speed_reference: f32) -> Measures {
        let last = |series: &[f32]| {
            let tail = &series[series.len().saturating_sub(self.window)..];
            if tail.is_empty() {
                0.0
            } else {
                tail.iter().sum::<f32>() / tail.len() as f32
            }
        };
        let growth = |energy: f32| {
            nan_max(energy - self.initial_energy - self.allowance, 0.0) / self.energy_scale
        };
        Measures {
            frames_run: self.frames_run,
            frames,
            energy_growth: growth(self.max_energy),
            final_energy_growth: growth(last(&self.energies)),
            peak_speed: self.peak_speed,
            speed_reference,
            final_speed: last(&self.speeds),
            settles,
            max_residual_cm: self.max_residual_cm,
            mean_residual_cm: last(&self.residuals),
            mean_angular_rad: last(&self.angular),
            shake: last(&self.shakes),
            failed: None,
        }
    }
}

/// The angular velocity scaled, per axis, to the speed it gives the body's surface: a linear
/// map, so differences of it across frames keep their meaning.
fn surface_angular_velocity(body: &crate::body::Body) -> Vec3 {
    let w = body.angular_velocity;
    match body.shape {
        Shape::Capsule {
            half_height,
            radius,
            axis,
        } => {
            let axis = body.orientation * axis.unit();
            let along = axis.dot(w) * axis;
            along * radius + (w - along) * (half_height + radius)
        }
        shape => w * shape.bounding_radius().min(1e3),
    }
}

/// Maximum that lets NaN through (a NaN measure must not hide as "small").
fn nan_max(a: f32, b: f32) -> f32 {
    if a.is_nan() || b.is_nan() {
        f32::NAN
    } else {
        a.max(b)
    }
}

impl Observer for Probe<'_> {
    fn begin(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        let world = &lab.world;
        self.initial_energy = metrics.total_energy();
        let mass: f32 = world
            .bodies
            .iter()
            .filter(|b| b.is_dynamic())
            .map(|b| b.mass)
            .sum();
        // the start's kinetic energy plus lifting every dynamic body one metre
        const LIFT_M: f32 = 1.0;
        self.energy_scale =
            metrics.kinetic_energy + mass * world.settings.gravity.length() * LIFT_M;
        self.max_energy = self.initial_energy;
        self.history = [Self::velocities(world), Self::velocities(world)];
        self.inner.begin(lab, metrics)
    }

    fn frame(&mut self, lab: &Lab, metrics: &FrameMetrics) -> anyhow::Result<()> {
        self.frames_run += 1;
        self.observe(&lab.world, metrics);
        self.inner.frame(lab, metrics)
    }

    fn failed(&mut self, lab: &Lab, error: &SimulationError) {
        let world = &lab.world;
        // the failing frame's state counts toward the peaks
        self.peak_speed = nan_max(self.peak_speed, Self::fastest_point(world));
        self.max_energy = nan_max(
            self.max_energy,
            world.kinetic_energy() + world.potential_energy(),
        );
        self.inner.failed(lab, error)
    }
}

/// The speed a scene can reach without the solver's help: its fastest start speed plus a
/// fall across the box holding its body centres, plus a metre.
fn speed_reference(world: &World) -> f32 {
    let centres = world
        .bodies
        .iter()
        .filter(|b| b.shape.bounding_radius().is_finite())
        .map(|b| b.position);
    let (low, high) = centres.fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    );
    let extent = (high - low).length();
    let start = Probe::fastest_point(world);
    start + (2.0 * world.settings.gravity.length() * (extent + 1.0)).sqrt()
}

/// Runs one case for one method through [`sim::run`], handing every frame to `observer` (so
/// the caller can record it). None when the case does not apply to the method. A NaN or an
/// explosion is a result (in [`Measures::failed`]); an error of the observer is returned.
pub fn run_case(
    case: &Case,
    method: Method,
    observer: &mut dyn Observer,
) -> anyhow::Result<Option<Outcome>> {
    let Some(built) = case.build_full(method) else {
        return Ok(None);
    };
    let Built {
        mut lab,
        frames,
        settles,
        energy_allowance,
    } = built;
    let reference = speed_reference(&lab.world);
    let window = (1.0 / case.dt).round().max(1.0) as usize; // frames in the last second
    let mut probe = Probe::new(observer, window, energy_allowance);
    let failed = match sim::run(&mut lab, frames, &mut probe) {
        Ok(_) => None,
        Err(error) => match error.downcast_ref::<SimulationError>() {
            Some(failure) => Some(failure.to_string()),
            None => return Err(error),
        },
    };
    let mut measures = probe.measures(frames, settles, reference);
    measures.failed = failed;
    Ok(Some(Outcome {
        case: case.name,
        method,
        verdict: verdict(&measures, &Criteria::default()),
        measures,
    }))
}

/// Runs the whole suite for every method without an observer.
pub fn run_suite() -> Vec<Outcome> {
    let mut outcomes = Vec::new();
    for case in suite() {
        for method in Method::ALL {
            let outcome =
                run_case(&case, method, &mut sim::NoObserver).expect("NoObserver never fails");
            outcomes.extend(outcome);
        }
    }
    outcomes
}

/// Thresholds of the verdict; the module docs give the measurements behind each default.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Criteria {
    /// Exploded: energy growth held over the last second above this.
    pub exploded_final_energy_growth: f32,
    /// Exploded: peak speed above this multiple of the scene's speed reference.
    pub exploded_speed_factor: f32,
    /// Exploded (torn apart): largest dislocation, mean over the last second (cm), above this.
    pub exploded_residual_cm: f32,
    /// Jittering: energy growth at any moment above this (a pop).
    pub jitter_energy_growth: f32,
    /// Jittering: energy growth held over the last second above this.
    pub jitter_final_energy_growth: f32,
    /// Jittering: largest dislocation, mean over the last second (cm), above this.
    pub jitter_residual_cm: f32,
    /// Jittering: a settling scene's fastest point, mean over the last second (m/s), above this.
    pub jitter_final_speed: f32,
    /// Jittering: shake, mean over the last second (m/s), above this.
    pub jitter_shake: f32,
}

impl Default for Criteria {
    fn default() -> Self {
        Criteria {
            exploded_final_energy_growth: 1.0,
            exploded_speed_factor: 5.0,
            exploded_residual_cm: 50.0,
            jitter_energy_growth: 0.5,
            jitter_final_energy_growth: 0.1,
            jitter_residual_cm: 5.0,
            jitter_final_speed: 0.2,
            jitter_shake: 0.1,
        }
    }
}

/// The first criterion a run trips, most severe first, with its verdict and a short reason;
/// None when the run is stable.
pub fn tripped(m: &Measures, c: &Criteria) -> Option<(Verdict, String)> {
    use Verdict::{Exploded, Jittering};
    if let Some(message) = &m.failed {
        // "frame N: body ..." -> "frame N"
        let frame = message.split(':').next().unwrap_or(message);
        return Some((Exploded, frame.to_string()));
    }
    let numbers = [
        m.energy_growth,
        m.final_energy_growth,
        m.peak_speed,
        m.final_speed,
        m.max_residual_cm,
        m.mean_residual_cm,
        m.mean_angular_rad,
        m.shake,
    ];
    if numbers.iter().any(|x| !x.is_finite()) {
        return Some((Exploded, "NaN".into()));
    }
    let checks = [
        (
            m.final_energy_growth > c.exploded_final_energy_growth,
            Exploded,
            format!("energy kept +{:.2}", m.final_energy_growth),
        ),
        (
            m.peak_speed > c.exploded_speed_factor * m.speed_reference,
            Exploded,
            format!("peak {:.0} m/s", m.peak_speed),
        ),
        (
            m.mean_residual_cm > c.exploded_residual_cm,
            Exploded,
            format!("torn {:.0} cm", m.mean_residual_cm),
        ),
        (
            m.final_energy_growth > c.jitter_final_energy_growth,
            Jittering,
            format!("energy kept +{:.2}", m.final_energy_growth),
        ),
        (
            m.energy_growth > c.jitter_energy_growth,
            Jittering,
            format!("energy pop +{:.2}", m.energy_growth),
        ),
        (
            m.mean_residual_cm > c.jitter_residual_cm,
            Jittering,
            format!("residual {:.1} cm", m.mean_residual_cm),
        ),
        (
            m.settles && m.final_speed > c.jitter_final_speed,
            Jittering,
            format!("end speed {:.2} m/s", m.final_speed),
        ),
        (
            m.shake > c.jitter_shake,
            Jittering,
            format!("shake {:.2} m/s", m.shake),
        ),
    ];
    checks
        .into_iter()
        .find(|(hit, _, _)| *hit)
        .map(|(_, verdict, why)| (verdict, why))
}

/// The verdict of a run: a pure function of its measures.
pub fn verdict(m: &Measures, criteria: &Criteria) -> Verdict {
    tripped(m, criteria).map_or(Verdict::Stable, |(v, _)| v)
}

/// Rows: cases; columns: methods; cells: the verdict and its key number (the criterion that
/// tripped, or the mean residual of a stable run); `-` where a case does not apply.
pub fn table_markdown(outcomes: &[Outcome]) -> String {
    let mut cases: Vec<&str> = Vec::new();
    for o in outcomes {
        if !cases.contains(&o.case) {
            cases.push(o.case);
        }
    }
    let mut out = String::from("| case |");
    for method in Method::ALL {
        out += &format!(" {method} |");
    }
    out += "\n|---|";
    out += &"---|".repeat(Method::ALL.len());
    out += "\n";
    for case in cases {
        out += &format!("| {case} |");
        for method in Method::ALL {
            let cell = match outcomes
                .iter()
                .find(|o| o.case == case && o.method == method)
            {
                None => "-".to_string(),
                Some(o) => match tripped(&o.measures, &Criteria::default()) {
                    Some((v, why)) => format!("{v} ({why})"),
                    None => format!("{} ({:.2} cm)", o.verdict, o.measures.mean_residual_cm),
                },
            };
            out += &format!(" {} |", cell.replace('|', "/"));
        }
        out += "\n";
    }
    out
}

/// Column names of [`table_csv`].
pub const CSV_HEADER: &str = "case,method,verdict,frames_run,frames,energy_growth,\
final_energy_growth,peak_speed_m_s,speed_reference_m_s,final_speed_m_s,settles,max_residual_cm,mean_residual_cm,mean_angular_rad,\
shake_m_s,failed";

/// One row per run, columns [`CSV_HEADER`] (the failure message quoted where it needs it).
pub fn table_csv(outcomes: &[Outcome]) -> String {
    crate::csv_table::to_text(
        CSV_HEADER,
        outcomes.iter().map(|o| {
            let m = &o.measures;
            vec![
                o.case.to_string(),
                o.method.to_string(),
                o.verdict.to_string(),
                m.frames_run.to_string(),
                m.frames.to_string(),
                format!("{:.4}", m.energy_growth),
                format!("{:.4}", m.final_energy_growth),
                format!("{:.3}", m.peak_speed),
                format!("{:.3}", m.speed_reference),
                format!("{:.4}", m.final_speed),
                m.settles.to_string(),
                format!("{:.4}", m.max_residual_cm),
                format!("{:.4}", m.mean_residual_cm),
                format!("{:.4}", m.mean_angular_rad),
                format!("{:.4}", m.shake),
                m.failed.clone().unwrap_or_default(),
            ]
        }),
    )
}
