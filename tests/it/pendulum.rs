//! Analytic check: a small-amplitude physical pendulum on an exact ball-and-socket joint swings
//! with period T = 2 pi sqrt(I_pivot / (m g L)) within 1% at dt = 1/240.

use rodlab::body::{Body, BodyKind};
use rodlab::constraint::{BallSocket, JointFlavour};
use rodlab::math::{Quat, Vec3};
use rodlab::shape::Shape;
use rodlab::world::{Settings, World};

fn pendulum(dt: f32, length: f32, amplitude: f32) -> World {
    let mut world = World::new(Settings {
        dt,
        iterations: 10,
        ..Settings::default()
    });
    let pivot = Vec3::new(0.0, 2.0, 0.0);
    let anchor = world.add_body(
        Body::new(
            "pivot",
            BodyKind::Fixed,
            Shape::Sphere { radius: 0.02 },
            1.0,
        )
        .with_pose(pivot, Quat::IDENTITY),
    );
    let bob_position = pivot + length * Vec3::new(amplitude.sin(), -amplitude.cos(), 0.0);
    let bob = world.add_body(
        Body::new(
            "bob",
            BodyKind::Dynamic,
            Shape::Sphere { radius: 0.05 },
            1.0,
        )
        .with_pose(bob_position, Quat::IDENTITY),
    );
    let joint =
        BallSocket::at_world_anchor("hinge", &world.bodies, anchor, bob, pivot, Quat::IDENTITY)
            .with_flavour(JointFlavour::Exact);
    world.add_constraint(joint);
    world
}

/// Mean period from upward zero crossings of the bob's x coordinate.
fn measured_period(world: &mut World, seconds: f32) -> f64 {
    let bob = world.find_body("bob").unwrap();
    let steps = (seconds / world.settings.dt) as usize;
    let mut crossings = Vec::new();
    let mut previous = world.body(bob).position.x;
    for _ in 0..steps {
        world.step().unwrap();
        let x = world.body(bob).position.x;
        if previous < 0.0 && x >= 0.0 {
            // linear interpolation of the crossing time
            let fraction = previous / (previous - x);
            crossings.push(world.time - world.settings.dt as f64 * (1.0 - fraction as f64));
        }
        previous = x;
    }
    assert!(crossings.len() >= 3, "too few swings: {crossings:?}");
    (crossings.last().unwrap() - crossings[0]) / (crossings.len() - 1) as f64
}

#[test]
fn small_amplitude_period_matches_analytic() {
    let (length, radius, mass, g) = (1.0f64, 0.05f64, 1.0f64, 9.81f64);
    let inertia_pivot = 0.4 * mass * radius * radius + mass * length * length;
    let analytic = 2.0 * std::f64::consts::PI * (inertia_pivot / (mass * g * length)).sqrt();
    let mut world = pendulum(1.0 / 240.0, length as f32, 0.05);
    let measured = measured_period(&mut world, 12.0);
    let error = (measured - analytic).abs() / analytic;
    assert!(
        error < 0.01,
        "period {measured:.5} s vs analytic {analytic:.5} s ({:.3}%)",
        100.0 * error
    );
}

#[test]
fn pendulum_keeps_its_length() {
    let mut world = pendulum(1.0 / 240.0, 1.0, 0.5);
    let bob = world.find_body("bob").unwrap();
    for _ in 0..2400 {
        world.step().unwrap();
        let length = (world.body(bob).position - Vec3::new(0.0, 2.0, 0.0)).length();
        assert!((length - 1.0).abs() < 1e-4, "length drifted to {length}");
    }
}

/// A capsule limb of 2 kg hinged at its top end, its centre 0.2 m below the hinge, tilted by
/// `amplitude` (rad) and let go, at 4 substeps of 4 iterations with `settings`' joint damping
/// and friction; the world, the limb and the hinge.
fn hanging_limb(settings: Settings, amplitude: f32) -> (World, rodlab::body::BodyId, Vec3) {
    use rodlab::shape::Axis;
    let mut world = World::new(Settings {
        dt: 1.0 / 60.0,
        substeps: 4,
        iterations: 4,
        ..settings
    });
    let pivot = Vec3::new(0.0, 2.0, 0.0);
    let top = world.add_body(
        Body::new("top", BodyKind::Fixed, Shape::Sphere { radius: 0.02 }, 1.0)
            .with_pose(pivot, Quat::IDENTITY),
    );
    let length = LIMB_LENGTH;
    let shape = Shape::Capsule {
        half_height: length - 0.04,
        radius: 0.04,
        axis: Axis::Y,
    };
    let tilt = Quat::from_rotation_z(amplitude);
    let limb = Body::new("limb", BodyKind::Dynamic, shape, 2.0)
        .with_pose(pivot + tilt * Vec3::new(0.0, -length, 0.0), tilt);
    let limb = world.add_body(limb);
    let joint =
        BallSocket::at_world_anchor("shoulder", &world.bodies, top, limb, pivot, Quat::IDENTITY)
            .with_flavour(JointFlavour::Exact);
    world.add_constraint(joint);
    (world, limb, pivot)
}

/// The hinge-to-centre distance of [`hanging_limb`] (m).
const LIMB_LENGTH: f32 = 0.2;

/// The limb's swing angle from straight down (rad, signed).
fn swing_angle(world: &World, limb: rodlab::body::BodyId, pivot: Vec3) -> f32 {
    let arm = world.body(limb).position - pivot;
    arm.x.atan2(-arm.y)
}

/// Largest swing angle (rad) of the hanging limb, per second over `seconds`, with joint damping
/// `coefficient` (N m s/rad); and the limb's moment of inertia about the hinge.
fn damped_limb_swings(coefficient: f32, seconds: usize) -> (Vec<f32>, f32) {
    let settings = Settings {
        joint_damping: coefficient,
        ..Settings::default()
    };
    let (mut world, limb, pivot) = hanging_limb(settings, 0.3);
    // about the swing axis, by the parallel-axis theorem
    let body = world.body(limb);
    let pivot_inertia = body.inertia.z + body.mass * LIMB_LENGTH * LIMB_LENGTH;
    let mut peaks = Vec::new();
    for _ in 0..seconds {
        let mut peak = 0.0f32;
        for _ in 0..60 {
            world.step().unwrap();
            peak = peak.max(swing_angle(&world, limb, pivot).abs());
        }
        peaks.push(peak);
    }
    (peaks, pivot_inertia)
}

/// Joint damping is a rotational dashpot across the joint (torque `-k w_rel`, `k` in N m s/rad),
/// so a limb swinging about its hinge slows like a damped pendulum, its amplitude falling at
/// `k / (2 I_pivot)` per second on top of the solver's own damping (measured with `k = 0`).
/// Checked from the amplitude after 1 and 4 s, within 10%, for two coefficients.
#[test]
fn joint_damping_slows_a_swinging_limb_at_its_predicted_rate() {
    let decay = |peaks: &[f32]| (peaks[0] / peaks[3]).ln() / 3.0;
    let (undamped, pivot_inertia) = damped_limb_swings(0.0, 4);
    for coefficient in [0.05, 0.15] {
        let (damped, _) = damped_limb_swings(coefficient, 4);
        let extra = decay(&damped) - decay(&undamped);
        let predicted = coefficient / (2.0 * pivot_inertia);
        assert!(
            (extra / predicted - 1.0).abs() < 0.1,
            "k = {coefficient}: the swing decays {extra:.3}/s faster than undamped, predicted {predicted:.3}/s ({damped:?} against {undamped:?})"
        );
    }
}

/// Joint friction is Coulomb's: a torque of at most `T` against the turn. A limb swinging from
/// `theta_1` then turns back at the `theta_2` where gravity's work pays friction's,
/// `m g d (cos theta_2 - cos theta_1) = T (theta_1 + theta_2)`: the swing shrinks by a fixed angle
/// per half swing (a dashpot's by a fixed fraction), and the limb stops dead once gravity's
/// torque at a turning point is under `T`. Checked per half swing within 10% of the drop (with
/// the solver's own loss, the fraction measured without friction, taken off) and at rest at the end, held
/// within the angle where `m g d sin theta = T`.
#[test]
fn joint_friction_stops_a_swinging_limb_as_coulomb_friction() {
    let torque = 0.1f32;
    let turning_points = |friction: f32| {
        let settings = Settings {
            joint_friction: friction,
            ..Settings::default()
        };
        let (mut world, limb, pivot) = hanging_limb(settings, 0.3);
        let (mut peaks, mut angles) = (vec![0.3f32], Vec::new());
        for _ in 0..600 {
            world.step().unwrap();
            angles.push(swing_angle(&world, limb, pivot));
        }
        for w in angles.windows(3) {
            if (w[1] - w[0]) * (w[2] - w[1]) < 0.0 && w[1].abs() > 1e-3 {
                peaks.push(w[1].abs());
            }
        }
        let speed = world.body(limb).linear_velocity.length();
        (peaks, angles[angles.len() - 1], speed)
    };
    let (free, _, _) = turning_points(0.0);
    let (held, end, speed) = turning_points(torque);
    let mgd = 2.0 * 9.81 * LIMB_LENGTH;
    // the next turning point after theta_1 by the energy balance above (bisection)
    let next = |theta_1: f32| {
        let balance = |t2: f32| mgd * (t2.cos() - theta_1.cos()) - torque * (theta_1 + t2);
        let (mut low, mut high) = (0.0f32, theta_1);
        for _ in 0..60 {
            let mid = 0.5 * (low + high);
            if balance(mid) > 0.0 {
                low = mid
            } else {
                high = mid
            }
        }
        low
    };
    let friction_angle = (torque / mgd).asin();
    let swings = held.len() - 1;
    assert!(swings >= 3, "too few half swings to measure: {held:?}");
    for i in 0..swings - 1 {
        // the solver's own loss is a fraction of the swing (about 4% per half swing here)
        let solver_loss = held[i] * (1.0 - free[i + 1] / free[i]);
        let measured = held[i] - held[i + 1] - solver_loss;
        let predicted = held[i] - next(held[i]);
        assert!(
            (measured / predicted - 1.0).abs() < 0.1,
            "half swing {i}: the swing shrank by {measured:.4} rad, Coulomb predicts {predicted:.4} ({held:?}, without friction {free:?})"
        );
    }
    assert!(
        end.abs() <= friction_angle * 1.05 && speed < 1e-3,
        "the limb ends at {end:.4} rad moving at {speed:.2e} m/s; friction holds it within {friction_angle:.4} rad"
    );
}
