//! Running the suite: the probe that measures a run frame by frame, the scene's speed
//! reference, and the runs of one case or of the whole suite.

use super::{suite, verdict, Built, Case, Criteria, Measures, Method, Outcome};
use crate::lab::Lab;
use crate::math::Vec3;
use crate::metrics::FrameMetrics;
use crate::shape::Shape;
use crate::sim::{self, Observer};
use crate::world::{SimulationError, World};

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
