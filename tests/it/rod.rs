//! The rod constraint (paper §5, `src/constraint/rod.rs`), checked against independent maths:
//!
//! 1. every analytic gradient (curve, length, bend, twist) against central finite differences;
//! 2. arcs built from a centre, radius and plane satisfy the curve (eq. 6) and length (eq. 9)
//!    constraints, and `arc_point` walks along them;
//! 3. `chord_ratio` is continuous across its series switch and exact at 0 and pi;
//! 4. a perturbed rod is projected back to a valid arc of its rest length in a few iterations;
//! 5. rod corrections keep the pair's linear momentum exactly and angular momentum to first order;
//! 6. `alpha_bend` / `alpha_twist` monotonically stiffen bending / twisting (0 = free);
//! 7. degenerate configurations (psi -> 0, psi -> pi, coincident centres) stay finite and smooth;
//! 8. the paper's twist (eq. 12) loses the sign and underestimates, the exact twist does not;
//! 9. the sampled arc and material frame start at body a and end at body b on a valid rod.
//!
//! Two limitations inherited from the paper are measured: the length correction along o^ only
//! does work on a freely bending rod (the full-gradient correction does not), and the mirrored
//! arc passes eq. 6 and 9 (an `#[ignore]`d test with the numbers; not fixed yet).
//!
//! Randomised tests use a fixed-seed xorshift generator, so every run sees the same cases.

use glam::{DQuat, DVec3};
use rodlab::body::{Body, BodyId, BodyKind};
use rodlab::constraint::rod::{
    arc_point, chord_ratio, curve_error, curve_gradient, curve_vector, length_error, offset_axis,
    twist_exact, twist_paper,
};
use rodlab::constraint::{BendTwist, Constraint, LengthCorrection, Rod, RodParams};
use rodlab::math::{angle_between, quat_from_rotation_vector, Quat, Vec3};
use rodlab::shape::{Axis, Shape};
use rodlab::world::{Settings, World};
use std::f32::consts::PI;

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

/// xorshift64* with a fixed seed: deterministic, no extra crates.
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Self {
        Rng(seed.max(1))
    }
    fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    /// Uniform in [0, 1).
    fn unit_interval(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit_interval()
    }
    /// Uniform on the unit sphere (rejection from the cube).
    fn direction64(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            let l2 = v.length_squared();
            if l2 > 1e-2 && l2 <= 1.0 {
                return v / l2.sqrt();
            }
        }
    }
    fn direction(&mut self) -> Vec3 {
        self.direction64().as_vec3().normalize()
    }
    fn vec_in_box(&mut self, half: f32) -> Vec3 {
        let h = half as f64;
        DVec3::new(self.range(-h, h), self.range(-h, h), self.range(-h, h)).as_vec3()
    }
    fn quat(&mut self) -> Quat {
        quat_from_rotation_vector(self.range(0.0, 3.0) as f32 * self.direction())
    }
}

/// Rod frame whose x axis is the unit tangent `t` (y, z completed arbitrarily but fixed).
fn frame_with_tangent(t: Vec3, spin: f32) -> Quat {
    Quat::from_rotation_arc(Vec3::X, t) * Quat::from_rotation_x(spin)
}

/// Largest angle between corresponding axes of two frames (atan2-accurate at small angles,
/// unlike `Quat::angle_between`, whose acos resolves nothing below ~7e-4 rad in f32).
fn frame_gap(a: Quat, b: Quat) -> f32 {
    [Vec3::X, Vec3::Y, Vec3::Z]
        .iter()
        .map(|&e| angle_between(a * e, b * e))
        .fold(0.0, f32::max)
}

fn cosine(a: Vec3, b: Vec3) -> f32 {
    a.dot(b) / (a.length() * b.length())
}

/// Central difference of `f(d)` along the three world axes: `d = +-h e_x`, `+-h e_y`, `+-h e_z`.
fn central_gradient(h: f32, mut f: impl FnMut(Vec3) -> f32) -> Vec3 {
    let component = |f: &mut dyn FnMut(Vec3) -> f32, e: Vec3| (f(h * e) - f(-h * e)) / (2.0 * h);
    Vec3::new(
        component(&mut f, Vec3::X),
        component(&mut f, Vec3::Y),
        component(&mut f, Vec3::Z),
    )
}

/// Asserts an analytic gradient against a finite-difference one: same direction and magnitude.
/// Returns the relative difference `|numeric - analytic| / |analytic|` (0 when both are tiny).
fn assert_gradient(what: &str, analytic: Vec3, numeric: Vec3) -> f32 {
    // Below this size a direction is meaningless; compare absolutely (f32 FD noise ~1e-4).
    if analytic.length() < 0.05 && numeric.length() < 0.05 {
        assert!(
            (analytic - numeric).length() < 2e-3,
            "{what}: analytic {analytic} vs finite differences {numeric}"
        );
        return 0.0;
    }
    // Direction within ~8 degrees and magnitude within 3%: truncation O(h^2) plus f32 rounding
    // of C (~1e-7 / 2h) are far below this, a wrong sign or missing term is far above.
    let c = cosine(analytic, numeric);
    let ratio = numeric.length() / analytic.length();
    assert!(
        c > 0.99 && (ratio - 1.0).abs() < 0.03,
        "{what}: analytic {analytic} vs finite differences {numeric} (cos {c}, |fd|/|an| {ratio})"
    );
    (numeric - analytic).length() / analytic.length()
}

fn capsule(name: &str, mass: f32, half_height: f32, radius: f32) -> Body {
    Body::new(
        name,
        BodyKind::Dynamic,
        Shape::Capsule {
            half_height,
            radius,
            axis: Axis::X,
        },
        mass,
    )
}

/// Pelvis (8 kg) and chest (12 kg) capsules 0.385 m apart along +y, joined by a straight rod.
fn pelvis_chest() -> (Vec<Body>, Rod) {
    let bodies = vec![
        capsule("pelvis", 8.0, 0.12, 0.1).with_pose(Vec3::new(0.0, 1.0, 0.0), Quat::IDENTITY),
        capsule("chest", 12.0, 0.15, 0.12).with_pose(Vec3::new(0.0, 1.385, 0.0), Quat::IDENTITY),
    ];
    let rod = Rod::instantiate("spine", &bodies, BodyId(0), BodyId(1), Vec3::Z).unwrap();
    (bodies, rod)
}

fn rod_state(rod: &Rod, bodies: &[Body]) -> rodlab::constraint::RodState {
    rod.state(&bodies[rod.body_a.index()], &bodies[rod.body_b.index()])
}

// ---------------------------------------------------------------------------------------------
// 1. Gradients against finite differences
// ---------------------------------------------------------------------------------------------

#[test]
fn gradients_match_finite_differences() {
    let mut rng = Rng::new(0x5eed_0001);
    // f32 central differences: h = 1e-3 balances truncation (h^2) against rounding (eps / h).
    let h = 1e-3;
    let (mut checked, mut worst) = (0, 0.0f32);
    while checked < 200 {
        let pa = rng.vec_in_box(0.5);
        let pb = pa + rng.range(0.2, 0.8) as f32 * rng.direction();
        let (ta, tb) = (rng.direction(), rng.direction());
        let c = curve_error(pa, ta, pb, tb);
        // Away from C = 0 and C = pi, where the angle is not differentiable.
        if !(0.2..PI - 0.2).contains(&c) || angle_between(ta, tb) > PI - 0.2 {
            continue;
        }
        checked += 1;
        let g = curve_gradient(pa, ta, pb, tb);
        let turn = |t: Vec3, d: Vec3| quat_from_rotation_vector(d) * t;
        let fd_pa = central_gradient(h, |d| curve_error(pa + d, ta, pb, tb));
        let fd_pb = central_gradient(h, |d| curve_error(pa, ta, pb + d, tb));
        let fd_ta = central_gradient(h, |d| curve_error(pa, turn(ta, d), pb, tb));
        let fd_tb = central_gradient(h, |d| curve_error(pa, ta, pb, turn(tb, d)));
        for (what, analytic, numeric) in [
            ("curve dC/dp_a", g.p_a, fd_pa),
            ("curve dC/dp_b", g.p_b, fd_pb),
            ("curve dC/dtheta_a", g.theta_a, fd_ta),
            ("curve dC/dtheta_b", g.theta_b, fd_tb),
        ] {
            worst = worst.max(assert_gradient(what, analytic, numeric));
        }

        // Length at fixed psi (tangents untouched): the gradient is +-o^.
        let l0 = rng.range(0.2, 1.0) as f32;
        let o = offset_axis(pa, pb, ta);
        let fd_len_b = central_gradient(h, |d| length_error(pa, ta, pb + d, tb, l0));
        let fd_len_a = central_gradient(h, |d| length_error(pa + d, ta, pb, tb, l0));
        worst = worst.max(assert_gradient("length dC/dp_b", o, fd_len_b));
        worst = worst.max(assert_gradient("length dC/dp_a", -o, fd_len_a));
        // The curve's positional gradient is across o^: the block of curve and length (the
        // paper's length moves along o^ only) is diagonal (`BendTwist::Block`).
        let along = g.p_b.dot(o) / g.p_b.length();
        assert!(
            along.abs() < 1e-5,
            "curve dC/dp_b . o^ = {along} of |dC/dp_b|"
        );

        // Bend: d psi / d theta_b = (t_a x t_b) / |t_a x t_b|.
        let fd_bend = central_gradient(h, |d| angle_between(ta, turn(tb, d)));
        let bend_axis = ta.cross(tb).normalize();
        worst = worst.max(assert_gradient("bend dpsi/dtheta_b", bend_axis, fd_bend));

        // Twist: turning F_b about its own tangent by h adds h; turning F_a about t_b removes h.
        let (fa, fb) = (rng.quat(), rng.quat());
        let (ta, tb) = (fa * Vec3::X, fb * Vec3::X);
        let tau = twist_exact(fa, fb);
        if angle_between(ta, tb) > PI - 0.2 || tau.abs() > PI - 0.2 {
            continue; // transport undefined at psi = pi; twist wraps at +-pi
        }
        let twist_b = |x: f32| twist_exact(fa, quat_from_rotation_vector(x * tb) * fb);
        let twist_a = |x: f32| twist_exact(quat_from_rotation_vector(x * tb) * fa, fb);
        let dtau_b = (twist_b(h) - twist_b(-h)) / (2.0 * h);
        let dtau_a = (twist_a(h) - twist_a(-h)) / (2.0 * h);
        // Derivative exactly +-1 in theory; f32 rounding of tau over 2h is ~1e-4.
        assert!(
            (dtau_b - 1.0).abs() < 2e-3,
            "dtau/dtheta_b about t_b = {dtau_b}, want 1"
        );
        assert!(
            (dtau_a + 1.0).abs() < 2e-3,
            "dtau/dtheta_a about t_b = {dtau_a}, want -1"
        );
        worst = worst.max((dtau_b - 1.0).abs()).max((dtau_a + 1.0).abs());
    }
    eprintln!("worst relative gradient difference: {worst:.2e}");
}

// ---------------------------------------------------------------------------------------------
// 2. Valid arcs satisfy the curve and length constraints
// ---------------------------------------------------------------------------------------------

/// An arc of radius `radius` about `centre` in the plane with unit normal `normal`, from the
/// direction `start` (unit, perpendicular to `normal`) through the angle `psi`, built in f64:
/// `[p_a, t_a, p_b, t_b]`; its length is `radius * psi`.
fn circle_arc(centre: DVec3, radius: f64, normal: DVec3, start: DVec3, psi: f64) -> [DVec3; 4] {
    let turn = DQuat::from_axis_angle(normal, psi);
    let ta = normal.cross(start).normalize();
    [
        centre + radius * start,
        ta,
        centre + radius * (turn * start),
        turn * ta,
    ]
}

#[test]
fn circular_arcs_satisfy_curve_and_length() {
    let mut rng = Rng::new(0x5eed_0002);
    let mut worst = [0.0f32; 5];
    for _ in 0..200 {
        let centre = DVec3::new(
            rng.range(-0.5, 0.5),
            rng.range(-0.5, 0.5),
            rng.range(-0.5, 0.5),
        );
        let radius = rng.range(0.1, 2.0);
        let normal = rng.direction64();
        let start = normal.cross(rng.direction64()).normalize();
        let psi = rng.range(0.01, 3.0);
        let [pa, ta, pb, tb] = circle_arc(centre, radius, normal, start, psi);
        let l0 = (radius * psi) as f32;
        let (pa, ta, pb, tb) = (pa.as_vec3(), ta.as_vec3(), pb.as_vec3(), tb.as_vec3());
        let scale = (radius as f32).max(1.0);
        let chord = (pb - pa).length();
        // The exact arc is rounded to f32 on input: that alone turns o^ (and the chord) by up to
        // ~eps (|p_a| + |p_b|) / |p_b - p_a| (1e-4 for a 1 mm chord at 1 m from the origin), so
        // the tolerance is 1e-5 plus that conditioning term; a wrong formula errs by ~psi.
        let conditioning = f32::EPSILON * (pa.length() + pb.length()) / chord;
        let tol = 1e-5 + conditioning;
        let case = format!("psi {psi:.4}, R {radius:.3}, chord {chord:.2e}");

        // eq. 6, vector form: t_a + t_b - 2 (t_a . o^) o^ = 0.
        let v = curve_vector(pa, ta, pb, tb).length();
        assert!(v < tol, "{case}: |C_curve| = {v:.3e} > {tol:.3e}");
        // Scalar form: angle_between is atan2(|a x b|, a . b), accurate at small angles (no acos
        // loss of sqrt(eps) ~ 3e-4), so the same tolerance as the vector form applies.
        let c = curve_error(pa, ta, pb, tb);
        assert!(c < tol, "{case}: curve_error = {c:.3e} > {tol:.3e}");
        // eq. 9 with l_0 = R psi; positions are O(1 + R), so f32 rounding is ~1e-7 (1 + R).
        let len = length_error(pa, ta, pb, tb, l0).abs();
        assert!(len < 1e-5 * scale, "{case}: length_error = {len:.3e} m");
        // The chord formula: l_0 chord_ratio(psi) = |p_b - p_a|, relative.
        let chord_err = (l0 * chord_ratio(angle_between(ta, tb)) - chord).abs() / chord;
        assert!(
            chord_err < tol,
            "{case}: l0 chord_ratio vs chord relative error {chord_err:.3e}"
        );
        // The arc from p_a with tangent t_a bent toward t_b ends at p_b; a sin/cos slip or a
        // wrong normal misses by ~R psi. Rounding of O(1 + R) coordinates: 1e-4 is generous.
        let end = (arc_point(pa, ta, tb, l0, 1.0) - pb).length();
        assert!(
            end < 1e-4 * scale,
            "{case}: arc end misses p_b by {end:.3e} m"
        );
        // Its midpoint is on the circle.
        let mid = (arc_point(pa, ta, tb, l0, 0.5).as_dvec3() - centre).length();
        let mid_err = (mid - radius).abs() as f32;
        assert!(
            mid_err < 1e-5 * scale,
            "{case}: arc midpoint {mid_err:.3e} m off the circle"
        );
        for (w, x) in worst
            .iter_mut()
            .zip([v, c, len / scale, chord_err, end / scale])
        {
            *w = w.max(x);
        }
    }
    eprintln!("worst |C_curve|, curve_error, |C_len|/R, chord rel, end/R: {worst:?}");
}

// ---------------------------------------------------------------------------------------------
// 3. chord_ratio
// ---------------------------------------------------------------------------------------------

#[test]
fn chord_ratio_is_continuous_and_exact_at_the_ends() {
    // 2 sin(psi/2)/psi is 1 - 4e-6 at the 1e-2 switch; series and closed form agree to ~1e-8
    // there, so 1e-6 catches a wrong series coefficient (psi^2/12 would differ by 4e-6).
    let below = chord_ratio(1e-2 * (1.0 - 1e-6));
    let above = chord_ratio(1e-2 * (1.0 + 1e-6));
    assert!(
        (below - above).abs() < 1e-6,
        "chord_ratio jumps at the series switch: {below} vs {above}"
    );
    // Both sides also match the f64 closed form.
    for psi in [1e-2 * (1.0 - 1e-6), 1e-2 * (1.0 + 1e-6), 5e-3, 2e-2] {
        let exact = 2.0 * (0.5 * psi as f64).sin() / psi as f64;
        let got = chord_ratio(psi) as f64;
        assert!(
            (got - exact).abs() < 1e-6,
            "chord_ratio({psi}) = {got}, want {exact}"
        );
    }
    assert_eq!(
        chord_ratio(0.0),
        1.0,
        "a straight rod's chord is its length"
    );
    // A half circle: chord 2R over length pi R.
    assert!(
        (chord_ratio(PI) - 2.0 / PI).abs() < 1e-6,
        "chord_ratio(pi) = {}",
        chord_ratio(PI)
    );
    // Monotone decreasing on [0, pi] (the chord shortens as the rod bends).
    let mut previous = chord_ratio(0.0);
    for i in 1..=1000 {
        let value = chord_ratio(PI * i as f32 / 1000.0);
        assert!(value < previous, "chord_ratio not decreasing at step {i}");
        previous = value;
    }
}

// ---------------------------------------------------------------------------------------------
// 4. Projection back to a valid arc
// ---------------------------------------------------------------------------------------------

/// Iterations of `Rod::solve` after which every perturbed pelvis-chest rod is a valid arc
/// (measured: at most 7 over the 50 random perturbations below; 10 leaves a margin).
const PROJECTION_ITERATIONS: usize = 10;

#[test]
fn perturbed_rod_returns_to_a_valid_arc() {
    let worst = returns_to_a_valid_arc(BendTwist::Sequential);
    eprintln!("iterations needed: at most {worst} (asserted {PROJECTION_ITERATIONS})");
}

/// The same with the rod's parts as blocks ([`BendTwist::Block`]): the length is measured on
/// the frames the curve starts from, so it carries what the curve's turn changes of psi into
/// the next iteration, yet the rod reaches a valid arc in as few iterations.
#[test]
fn perturbed_rod_returns_to_a_valid_arc_with_the_parts_as_blocks() {
    let worst = returns_to_a_valid_arc(BendTwist::Block);
    eprintln!("block: iterations needed: at most {worst} (asserted {PROJECTION_ITERATIONS})");
}

/// 50 random perturbations of the pelvis-chest rod (no bend or twist stiffness), each projected
/// [`PROJECTION_ITERATIONS`] times; returns the most iterations any needed.
fn returns_to_a_valid_arc(bend_twist: BendTwist) -> usize {
    let mut rng = Rng::new(0x5eed_0004);
    let mut worst_needed = 0;
    let mut worst_left = 0.0f32;
    for trial in 0..50 {
        let (mut bodies, mut rod) = pelvis_chest();
        rod.params.alpha_bend = 0.0;
        rod.params.alpha_twist = 0.0;
        rod.params.bend_twist = bend_twist;
        // Move the chest 2-3 cm and turn it 0.3 rad, both in random directions.
        let chest = &bodies[1];
        let shift = rng.range(0.02, 0.03) as f32 * rng.direction();
        let turn = quat_from_rotation_vector(0.3 * rng.direction());
        let (p, q) = (chest.position + shift, turn * chest.orientation);
        bodies[1].set_pose(p, q);
        let constraint = Constraint::Rod(rod.clone());
        let mut history = vec![rod_state(&rod, &bodies)];
        for _ in 0..PROJECTION_ITERATIONS {
            constraint.solve(&mut bodies);
            history.push(rod_state(&rod, &bodies));
        }
        let start = history[0];
        let end = *history.last().unwrap();
        // Hard constraints: 0.1 mm and 1 mrad are far below what a ragdoll shows, and far above
        // the f32 floor (~1e-7) the projection reaches.
        assert!(
            end.length_error.abs() < 1e-4 && end.curve_error < 1e-3,
            "trial {trial}: after {PROJECTION_ITERATIONS} iterations length error {:.3e} m, curve \
             error {:.3e} rad (start {:.3e} m, {:.3e} rad)",
            end.length_error,
            end.curve_error,
            start.length_error,
            start.curve_error
        );
        // The perturbation was real, and the curve error falls at every iteration until it
        // reaches the f32 floor.
        assert!(start.curve_error > 0.05 || start.length_error.abs() > 1e-3);
        for (k, pair) in history.windows(2).enumerate() {
            if pair[0].curve_error > 1e-5 {
                assert!(
                    pair[1].curve_error < pair[0].curve_error,
                    "trial {trial}: curve error rose at iteration {k}: {:.3e} -> {:.3e}",
                    pair[0].curve_error,
                    pair[1].curve_error
                );
            }
        }
        let left = history[1..]
            .iter()
            .map(|s| s.length_error.abs())
            .fold(0.0, f32::max);
        worst_left = worst_left.max(left);
        // Sequentially the length error is removed last in each iteration, so it is ~1e-8
        // after the first one. As blocks, what is left is what the curve's turn changed of
        // psi (measured: at most 1.9 mm, from perturbations of 2-3 cm and 0.3 rad); without
        // the length correction it would be centimetres.
        let bound = match bend_twist {
            BendTwist::Sequential => 1e-5,
            BendTwist::Block => 5e-3,
        };
        assert!(
            left < bound,
            "trial {trial}: length error {left:.3e} m left by an iteration"
        );
        let needed = history
            .iter()
            .position(|s| s.length_error.abs() < 1e-4 && s.curve_error < 1e-3)
            .unwrap();
        worst_needed = worst_needed.max(needed);
    }
    eprintln!("{bend_twist:?}: largest length error after an iteration {worst_left:.3e} m");
    worst_needed
}

// ---------------------------------------------------------------------------------------------
// 5. Momentum of the pair
// ---------------------------------------------------------------------------------------------

fn zero_gravity() -> Settings {
    Settings {
        gravity: Vec3::ZERO,
        dt: 1.0 / 60.0,
        iterations: 20,
        ..Settings::default()
    }
}

/// Net momentum of a pelvis-chest pair (centred on the origin, at rest, no gravity) after one
/// step, the chest moved by `e` metres and turned by `25 e` rad off the straight rod, relative to
/// the momenta the rod created: (linear, angular about the origin).
///
/// The created angular momentum is counted term by term, `sum_i |I_i w_i| + |p_i x m_i v_i|`: the
/// curve correction turns both bodies the same way and balances that with opposite orbital motion
/// of the pair, so one body's total `I w + p x m v` nearly cancels and is no measure of what the
/// rod did (it gives net/created ~0.5 for any error size).
fn rod_net_over_created(e: f32, alpha: f32) -> (f32, f32) {
    let (mut bodies, mut rod) = pelvis_chest();
    for body in &mut bodies {
        let centred = body.position - Vec3::new(0.0, 1.1925, 0.0);
        body.set_pose(centred, body.orientation);
    }
    rod.params.alpha_bend = alpha;
    rod.params.alpha_twist = alpha;
    let chest = &bodies[1];
    let p = chest.position + e * Vec3::new(0.6, 0.5, 0.6);
    let q = quat_from_rotation_vector(25.0 * e * Vec3::new(0.3, 0.5, 0.8).normalize())
        * chest.orientation;
    bodies[1].set_pose(p, q);
    let mut world = World::new(zero_gravity());
    for body in bodies {
        world.add_body(body);
    }
    world.constraints.push(Constraint::Rod(rod));
    world.step().unwrap();
    let (mut p, mut l, mut created_p, mut created_l) = (Vec3::ZERO, Vec3::ZERO, 0.0, 0.0);
    for body in &world.bodies {
        p += body.linear_momentum();
        l += body.angular_momentum();
        created_p += body.linear_momentum().length();
        let spin = body.inertia_world() * body.angular_velocity;
        let orbital = body.position.cross(body.linear_momentum());
        created_l += spin.length() + orbital.length();
    }
    (p.length() / created_p, l.length() / created_l)
}

/// Rod corrections are equal and opposite (length, bend, twist) or follow the full gradient of a
/// constraint invariant under moving the pair rigidly (curve), so linear momentum is conserved up
/// to rounding and angular momentum to first order in the correction (position-level solver:
/// per-step frozen inertia, first-order quaternion updates). Asserted: tiny net linear momentum,
/// net angular momentum shrinking at least like the error, and below 1% at the smallest error.
#[test]
fn rod_corrections_conserve_momentum_of_the_pair() {
    for (label, alpha) in [("bend+twist alpha 0.5", 0.5), ("curve+length only", 0.0)] {
        let ratios: Vec<(f32, f32)> = [0.004, 0.002, 0.001]
            .iter()
            .map(|&e| rod_net_over_created(e, alpha))
            .collect();
        eprintln!("{label}: (linear, angular) net/created = {ratios:?}");
        for (linear, _) in &ratios {
            // f32 rounding of the preview poses only.
            assert!(
                *linear < 1e-4,
                "{label}: net linear momentum {linear} of created"
            );
        }
        let angular: Vec<f32> = ratios.iter().map(|r| r.1).collect();
        // First order: halving the error at least roughly halves the residual ratio.
        assert!(
            angular[1] < 0.6 * angular[0] && angular[2] < 0.6 * angular[1],
            "{label}: net angular momentum not first order in the error: {angular:?}"
        );
        // 1 mm / 0.025 rad perturbation: well under 1% (an unbalanced correction leaves net ~
        // created, e.g. the curve fix without its positional part).
        assert!(
            angular[2] < 0.01,
            "{label}: net angular momentum {:.3}% of created",
            100.0 * angular[2]
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 6. Soft bending and twisting
// ---------------------------------------------------------------------------------------------

/// A fixed pelvis-like body at the origin and a dynamic 2 kg capsule 0.385 m along +x, joined
/// by a straight rod (tangent +x).
fn cantilever(settings: Settings, alpha_bend: f32, alpha_twist: f32) -> World {
    let mut world = World::new(settings);
    let root = Body::new(
        "root",
        BodyKind::Fixed,
        Shape::Capsule {
            half_height: 0.12,
            radius: 0.1,
            axis: Axis::X,
        },
        8.0,
    );
    let a = world.add_body(root);
    let b = world.add_body(
        capsule("tip", 2.0, 0.1, 0.05).with_pose(Vec3::new(0.385, 0.0, 0.0), Quat::IDENTITY),
    );
    let mut rod = Rod::instantiate("rod", &world.bodies, a, b, Vec3::Y).unwrap();
    rod.params.alpha_bend = alpha_bend;
    rod.params.alpha_twist = alpha_twist;
    world.constraints.push(Constraint::Rod(rod));
    world
}

fn rod_of(world: &World) -> &Rod {
    match &world.constraints[0] {
        Constraint::Rod(rod) => rod,
        _ => unreachable!(),
    }
}

#[test]
fn alpha_bend_stiffens_bending_monotonically() {
    let alphas = [0.0, 0.05, 0.2, 0.6, 1.0];
    let mut finals = Vec::new();
    for &alpha in &alphas {
        let mut world = cantilever(Settings::default(), alpha, 0.0);
        for frame in 1..=60 {
            world.step().unwrap();
            let s = rod_state(rod_of(&world), &world.bodies);
            if alpha == 0.0 && frame == 12 {
                // Free bending: after 0.2 s the tip has swung well down along a valid arc
                // (measured psi 1.09; the hard constraints hold to the f32 floor).
                assert!(s.psi > 0.5, "alpha_b = 0: psi only {} after 0.2 s", s.psi);
                assert!(s.length_error.abs() < 1e-5 && s.curve_error < 1e-5, "{s:?}");
            }
        }
        let s = rod_state(rod_of(&world), &world.bodies);
        finals.push(s.psi);
    }
    eprintln!("final psi per alpha_b {alphas:?}: {finals:?}");
    for (k, pair) in finals.windows(2).enumerate() {
        assert!(
            pair[1] < pair[0],
            "psi not decreasing from alpha_b {} to {}: {finals:?}",
            alphas[k],
            alphas[k + 1]
        );
    }
    // Fully stiff: only the sag gravity adds within the last iterations (measured 5e-4 rad).
    assert!(finals[4] < 0.01, "alpha_b = 1 still bends by {}", finals[4]);
    // Free: the tip swings down (after 60 frames it has passed psi = pi, see
    // `curve_and_length_reject_the_mirrored_arc`).
    assert!(finals[0] > 0.5, "alpha_b = 0 bends only {}", finals[0]);
}

#[test]
fn alpha_twist_stiffens_twisting_monotonically() {
    let alphas = [0.0, 0.05, 0.2, 0.6, 1.0];
    // Four iterations in one step: each removes the fraction alpha_t of tau (one step only, as
    // later steps carry the turn over as angular velocity and the soft twist rings).
    let settings = Settings {
        iterations: 4,
        ..zero_gravity()
    };
    let mut taus = Vec::new();
    for &alpha in &alphas {
        let mut world = cantilever(settings.clone(), 0.0, alpha);
        let tip = &world.bodies[1];
        let (p, q) = (tip.position, Quat::from_rotation_x(0.5) * tip.orientation);
        world.bodies[1].set_pose(p, q);
        let before = rod_state(rod_of(&world), &world.bodies);
        assert!(
            (before.tau - 0.5).abs() < 1e-5,
            "set-up twist {}",
            before.tau
        );
        world.step().unwrap();
        let tau = rod_state(rod_of(&world), &world.bodies).tau;
        // 0.5 (1 - alpha)^4, up to the first-order quaternion update (a 0.5 rad turn becomes
        // 2 atan(0.25) = 0.490 rad, caught up by the next iteration): 3e-3 separates the alphas.
        let expected = 0.5 * (1.0 - alpha).powi(4);
        assert!(
            (tau - expected).abs() < 3e-3,
            "alpha_t {alpha}: tau {tau} after 4 iterations, want {expected}"
        );
        taus.push(tau.abs());
    }
    eprintln!("|tau| per alpha_t {alphas:?}: {taus:?}");
    for (k, pair) in taus.windows(2).enumerate() {
        assert!(
            pair[1] < pair[0],
            "|tau| not decreasing from alpha_t {} to {}: {taus:?}",
            alphas[k],
            alphas[k + 1]
        );
    }
    // Free twist: nothing acts on it, for many steps.
    let mut world = cantilever(zero_gravity(), 0.0, 0.0);
    let tip = &world.bodies[1];
    let (p, q) = (tip.position, Quat::from_rotation_x(0.5) * tip.orientation);
    world.bodies[1].set_pose(p, q);
    for _ in 0..30 {
        world.step().unwrap();
    }
    let tau = rod_state(rod_of(&world), &world.bodies).tau;
    // No correction touches a pure twist, so only rounding moves it.
    assert!(
        (tau - 0.5).abs() < 1e-3,
        "alpha_t = 0: tau drifted to {tau}"
    );
}

// ---------------------------------------------------------------------------------------------
// 7. Degenerate configurations
// ---------------------------------------------------------------------------------------------

/// A rod whose frames are the bodies' orientations (local frames identity), rest length `l0`,
/// between two 5 kg capsules at the given poses. Not instantiated: any configuration is allowed.
fn posed_rod(pa: Vec3, fa: Quat, pb: Vec3, fb: Quat, l0: f32, alpha: f32) -> (Vec<Body>, Rod) {
    let bodies = vec![
        capsule("a", 5.0, 0.1, 0.05).with_pose(pa, fa),
        capsule("b", 5.0, 0.1, 0.05).with_pose(pb, fb),
    ];
    let rod = Rod {
        name: "posed".into(),
        body_a: BodyId(0),
        body_b: BodyId(1),
        local_frame_a: Quat::IDENTITY,
        local_frame_b: Quat::IDENTITY,
        rest_length: l0,
        params: RodParams {
            alpha_bend: alpha,
            alpha_twist: alpha,
            ..RodParams::default()
        },
    };
    (bodies, rod)
}

fn all_finite(bodies: &[Body]) -> bool {
    bodies
        .iter()
        .all(|b| b.position.is_finite() && b.orientation.is_finite())
}

/// Solves 20 iterations with both alphas 0 and 0.5 and checks every pose and sample stays finite.
fn assert_solve_and_sample_finite(what: &str, pa: Vec3, fa: Quat, pb: Vec3, fb: Quat, l0: f32) {
    for alpha in [0.0, 0.5] {
        let (mut bodies, rod) = posed_rod(pa, fa, pb, fb, l0, alpha);
        for k in 0..=10 {
            let (point, frame) = rod.sample(&bodies[0], &bodies[1], k as f32 / 10.0);
            assert!(
                point.is_finite() && frame.is_finite(),
                "{what}: sample at s = {} is {point} {frame}",
                k as f32 / 10.0
            );
        }
        let state = rod_state(&rod, &bodies);
        assert!(
            [state.psi, state.tau, state.length_error, state.curve_error]
                .iter()
                .all(|x| x.is_finite()),
            "{what}: state {state:?}"
        );
        let constraint = Constraint::Rod(rod);
        for _ in 0..20 {
            constraint.solve(&mut bodies);
        }
        assert!(
            all_finite(&bodies),
            "{what} (alpha {alpha}): solve gave {bodies:?}"
        );
    }
}

#[test]
fn degenerate_configurations_stay_finite_and_continuous() {
    let l0 = 0.385;
    let pa = Vec3::new(0.1, 1.0, -0.2);
    let ta = Vec3::new(0.3, 0.9, 0.2).normalize();
    let side = ta.any_orthonormal_vector();
    let fa = frame_with_tangent(ta, 0.4);

    // psi -> 0: tangents 1e-7 rad apart (and exactly equal).
    for tiny in [1e-7, 0.0] {
        let fb = quat_from_rotation_vector(tiny * side) * fa;
        let tb = fb * Vec3::X;
        for k in 0..=10 {
            let s = k as f32 / 10.0;
            let point = arc_point(pa, ta, tb, l0, s);
            // Straight to within f32 rounding of O(1) coordinates.
            assert!(
                (point - (pa + s * l0 * ta)).length() < 1e-6,
                "psi = {tiny}: arc_point({s}) = {point} is off the straight line"
            );
        }
        let pb = pa + l0 * ta;
        let g = curve_gradient(pa, ta, pb, tb);
        assert!(
            g.p_a.is_finite()
                && g.theta_a.is_finite()
                && g.p_b.is_finite()
                && g.theta_b.is_finite()
        );
        assert!(curve_error(pa, ta, pb, tb) < 1e-6);
        assert!(length_error(pa, ta, pb, tb, l0).abs() < 1e-6);
        assert_solve_and_sample_finite("psi -> 0", pa, fa, pb, fb, l0);
    }

    // psi -> pi: t_b = -t_a exactly and 1e-6 rad short of it, with p_b ahead, beside and on
    // top of p_a.
    for short in [0.0, 1e-6] {
        let fb = quat_from_rotation_vector((PI - short) * side) * fa;
        let tb = fb * Vec3::X;
        for pb in [pa + 0.245 * ta, pa + 0.245 * side, pa] {
            let g = curve_gradient(pa, ta, pb, tb);
            let values = [
                curve_error(pa, ta, pb, tb),
                length_error(pa, ta, pb, tb, l0),
                twist_exact(fa, fb),
                twist_paper(fa, fb),
            ];
            assert!(
                values.iter().all(|x| x.is_finite())
                    && g.p_a.is_finite()
                    && g.theta_a.is_finite()
                    && g.p_b.is_finite()
                    && g.theta_b.is_finite(),
                "psi = pi - {short}, p_b - p_a = {}: {values:?} {g:?}",
                pb - pa
            );
            assert_solve_and_sample_finite("psi -> pi", pa, fa, pb, fb, l0);
        }
    }

    // Coincident centres.
    let fb = quat_from_rotation_vector(0.3 * side) * fa;
    let g = curve_gradient(pa, ta, pa, fb * Vec3::X);
    assert!(
        g.p_a.is_finite() && g.theta_a.is_finite() && g.p_b.is_finite() && g.theta_b.is_finite()
    );
    assert_solve_and_sample_finite("p_a = p_b", pa, fa, pa, fb, l0);
    let bodies = vec![
        capsule("a", 5.0, 0.1, 0.05).with_pose(pa, Quat::IDENTITY),
        capsule("b", 5.0, 0.1, 0.05).with_pose(pa, Quat::IDENTITY),
    ];
    let error = Rod::instantiate("r", &bodies, BodyId(0), BodyId(1), Vec3::Z).unwrap_err();
    assert!(error.contains("coincide"), "unclear error: {error}");

    // Continuity near psi = 0: with p_b = p_a + l0 t_a and t_b turned by psi, the exact values
    // are curve_error = psi (r = t_a) and length_error = l0 (1 - 2 sin(psi/2) / psi), smooth in
    // psi; any jump at the series switches (1e-3 in arc_point, 1e-2 in chord_ratio) would show.
    // p_a at the origin so that the only rounding is that of p_b = l0 t_a (|p_b| = 0.385):
    // it turns o^ by ~eps ~ 1e-7 rad and changes |p_b - p_a| by ~3e-8 m.
    let (pa, pb) = (Vec3::ZERO, l0 * ta);
    for psi in [
        1e-4f32,
        1e-3,
        2e-3,
        1e-2 * (1.0 - 1e-5),
        1e-2 * (1.0 + 1e-5),
        0.1,
    ] {
        let tb = quat_from_rotation_vector(psi * side) * ta;
        let psi = angle_between(ta, tb); // the angle actually built, after f32 rounding
        let c = curve_error(pa, ta, pb, tb);
        let len = length_error(pa, ta, pb, tb, l0);
        let psi64 = psi as f64;
        let expected_len = l0 as f64 * (1.0 - 2.0 * (0.5 * psi64).sin() / psi64);
        assert!((c - psi).abs() < 3e-7, "psi {psi}: curve_error {c}");
        assert!(
            (len as f64 - expected_len).abs() < 1e-7,
            "psi {psi}: length_error {len}, want {expected_len}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 8. The paper's twist against the exact twist
// ---------------------------------------------------------------------------------------------

#[test]
fn paper_twist_loses_the_sign_and_underestimates() {
    let frame_a = Quat::IDENTITY; // tangent +x
    let psi: f32 = 1.0;
    let mut paper = Vec::new();
    for tau in [0.3f32, -0.3] {
        // Bend by psi about the binormal z, then a true twist tau about the new tangent.
        let frame_b = Quat::from_rotation_z(psi) * Quat::from_rotation_x(tau);
        let exact = twist_exact(frame_a, frame_b);
        // Swing-twist of exact quaternions: f32 rounding only.
        assert!(
            (exact - tau).abs() < 1e-4,
            "exact twist {exact}, want {tau}"
        );
        let p = twist_paper(frame_a, frame_b);
        // Design notes: xi = 2 acos(cos(psi/2) cos(tau/2)), tau_paper = xi - psi = 0.040.
        let xi = 2.0 * ((0.5 * psi as f64).cos() * (0.5 * tau as f64).cos()).acos();
        let expected = (xi - psi as f64) as f32;
        assert!((expected - 0.040).abs() < 1e-3);
        // xi - psi is a difference of two ~1 rad angles: 2e-3 covers f32 log-map rounding.
        assert!(
            (p - expected).abs() < 2e-3,
            "paper twist {p} for tau {tau}, want {expected}"
        );
        assert!(
            p.abs() < 0.2 * 0.3,
            "paper twist {p} does not underestimate"
        );
        paper.push(p);
    }
    assert!(
        (paper[0] - paper[1]).abs() < 1e-4,
        "paper twist should not see the sign: {paper:?}"
    );
    eprintln!("paper twist for tau = +-0.3 at psi = 1: {paper:?}");
}

// ---------------------------------------------------------------------------------------------
// 9. The sampled arc joins the bodies
// ---------------------------------------------------------------------------------------------

#[test]
fn sample_runs_from_body_a_to_body_b() {
    let mut rng = Rng::new(0x5eed_0009);
    for _ in 0..50 {
        // A valid arc of radius R through psi, with a twist tau between the end frames.
        let (radius, psi, tau) = (
            rng.range(0.2, 1.5),
            rng.range(0.05, 2.5),
            rng.range(-1.0, 1.0),
        );
        let normal = rng.direction64();
        let start = normal.cross(rng.direction64()).normalize();
        let centre = DVec3::new(rng.range(-0.3, 0.3), rng.range(0.5, 1.0), 0.0);
        let [pa, ta, pb, _] = circle_arc(centre, radius, normal, start, psi);
        let fa =
            DQuat::from_rotation_arc(DVec3::X, ta) * DQuat::from_rotation_x(rng.range(-3.0, 3.0));
        let fb = DQuat::from_axis_angle(normal, psi) * fa * DQuat::from_rotation_x(tau);
        let l0 = (radius * psi) as f32;
        let (fa, fb) = (fa.as_quat(), fb.as_quat());
        let (bodies, rod) = posed_rod(pa.as_vec3(), fa, pb.as_vec3(), fb, l0, 0.0);
        let twist = rod_state(&rod, &bodies).tau;
        assert!((twist - tau as f32).abs() < 1e-4, "tau {twist}, want {tau}");
        for (s, point, frame) in [(0.0, pa, fa), (1.0, pb, fb)] {
            let (p, f) = rod.sample(&bodies[0], &bodies[1], s);
            // f32 rounding of O(1) coordinates and of the frame composition.
            assert!(
                (p.as_dvec3() - point).length() < 1e-5,
                "s = {s}: {p} vs {point}"
            );
            let gap = frame_gap(f, frame);
            assert!(gap < 1e-5, "s = {s}: frame off by {gap} rad");
        }
        // In between: on the circle, tangent along the frame's x axis, twisted by tau s.
        for k in 1..10 {
            let s = k as f32 / 10.0;
            let (p, f) = rod.sample(&bodies[0], &bodies[1], s);
            let off_circle = ((p.as_dvec3() - centre).length() - radius).abs();
            assert!(off_circle < 1e-5, "s = {s}: {off_circle} m off the circle");
            let tangent = normal.cross((p.as_dvec3() - centre).normalize()).as_vec3();
            let off_tangent = angle_between(f * Vec3::X, tangent);
            assert!(
                off_tangent < 1e-5,
                "s = {s}: frame {off_tangent} rad off the tangent"
            );
            let natural = Quat::from_axis_angle(normal.as_vec3(), psi as f32 * s) * fa;
            let material_twist = rodlab::math::twist_angle(natural.inverse() * f, Vec3::X);
            assert!(
                (material_twist - tau as f32 * s).abs() < 1e-5,
                "s = {s}: material twist {material_twist}, want {}",
                tau as f32 * s
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Known defects (ignored so the suite stays green; see each reason)
// ---------------------------------------------------------------------------------------------

/// `arc_point` against the f64 arc `p_a + l0 (sin(psi s)/psi t_a + 2 sin^2(psi s/2)/psi k)`.
#[test]
fn arc_point_is_accurate_across_its_series_switch() {
    let l0 = 0.385f32;
    let at = |psi: f32, s: f32| {
        let tb = Vec3::new(psi.cos(), psi.sin(), 0.0);
        arc_point(Vec3::ZERO, Vec3::X, tb, l0, s)
    };
    let mut worst = 0.0f64;
    for k in 0..=200 {
        let psi = 1e-4 * 1.02f32.powi(k); // 1e-4 .. 5e-3 rad
        let tb = Vec3::new(psi.cos(), psi.sin(), 0.0);
        let psi64 = angle_between(Vec3::X, tb) as f64;
        for i in 0..=10 {
            let s = i as f64 / 10.0;
            let exact = DVec3::new(
                (psi64 * s).sin() / psi64,
                2.0 * (0.5 * psi64 * s).sin().powi(2) / psi64,
                0.0,
            ) * l0 as f64;
            worst = worst.max((at(psi, s as f32).as_dvec3() - exact).length());
        }
    }
    let jump = (at(1e-3 * (1.0 - 1e-6), 1.0) - at(1e-3 * (1.0 + 1e-6), 1.0)).length();
    eprintln!("arc_point: worst error {worst:.2e} m, jump at the switch {jump:.2e} m");
    // f32 rounding of O(l0) coordinates is ~3e-8 m; 1e-6 m leaves a wide margin.
    assert!(worst < 1e-6, "arc_point off the exact arc by {worst:.2e} m");
    assert!(
        jump < 1e-6,
        "arc_point jumps by {jump:.2e} m at the series switch"
    );
}

/// Eq. 6 is a half turn about o^, the same for o^ and -o^, and eq. 9 only sees |p_b - p_a|: so a
/// valid arc with p_b mirrored through p_a (p_b behind body a's tangent) reports no violation,
/// although no arc of length l0 leaving p_a along t_a reaches it.
#[test]
#[ignore = "limitation inherited from the paper: curve (eq. 6) and length (eq. 9) accept the \
            arc mirrored through p_a (violation 0, arc end 0.96 m from p_b for a 0.5 m rod); a \
            free rod under gravity reaches it (cantilever, alpha_b = 0: psi passes pi at frame \
            21, then t_a . o^ < 0 with zero reported violation)"]
fn curve_and_length_reject_the_mirrored_arc() {
    let (l0, psi) = (0.5f32, 1.0f32);
    let (pa, ta) = (Vec3::new(0.0, 1.0, 0.0), Vec3::X);
    let fb = Quat::from_rotation_z(psi);
    let pb = arc_point(pa, ta, fb * Vec3::X, l0, 1.0);
    let (bodies, rod) = posed_rod(pa, Quat::IDENTITY, pb, fb, l0, 0.0);
    let valid = rod.violation(&bodies[0], &bodies[1]);
    assert!(
        valid.dislocation < 1e-6 && valid.angular < 1e-5,
        "{valid:?}"
    );
    let mirrored = pa - (pb - pa);
    let (bodies, rod) = posed_rod(pa, Quat::IDENTITY, mirrored, fb, l0, 0.0);
    let v = rod.violation(&bodies[0], &bodies[1]);
    let miss = (arc_point(pa, ta, fb * Vec3::X, l0, 1.0) - mirrored).length();
    eprintln!("mirrored arc: violation {v:?}, arc end misses p_b by {miss} m");
    assert!(
        v.dislocation > 1e-3 || v.angular > 1e-3,
        "the mirrored arc passes as valid: {v:?} (arc end {miss} m from p_b)"
    );
}

/// Largest energy gained (J) over potential energy released (J) while a free cantilever rod
/// (alpha_b = 0) falls to psi = 2, at dt = 1/240.
fn free_rod_energy_gain(correction: LengthCorrection) -> f32 {
    let settings = Settings {
        dt: 1.0 / 240.0,
        ..Settings::default()
    };
    let mut world = cantilever(settings, 0.0, 0.0);
    if let Constraint::Rod(rod) = &mut world.constraints[0] {
        rod.params.length_correction = correction;
    }
    let energy = |w: &World| w.kinetic_energy() + w.potential_energy();
    let e0 = energy(&world);
    let (mut worst, mut released) = (0.0f32, 0.0f32);
    loop {
        world.step().unwrap();
        released = released.max(-world.potential_energy());
        worst = worst.max((energy(&world) - e0) / released.max(1e-6));
        if rod_state(rod_of(&world), &world.bodies).psi > 2.0 {
            return worst;
        }
    }
}

/// Where the paper's method fails: its length correction moves the bodies along o^ only (at
/// fixed psi), not along the full gradient of eq. 9, so its force does work on the free bending
/// motion. Measured: +49% of the released potential energy by psi = 2, the same at dt = 1/60,
/// 1/240, 1/1000 and with 20 or 100 iterations.
#[test]
fn offset_length_correction_does_work_on_a_free_rod() {
    let gain = free_rod_energy_gain(LengthCorrection::Offset);
    assert!(gain > 0.2, "gain {:.1}% of released energy", 100.0 * gain);
}

/// The remedy: correcting eq. 9 along its full gradient (positions and the turn through psi)
/// makes the constraint force workless; the free rod no longer gains energy (1% allows for the
/// solver's own first-order, dissipative errors).
#[test]
fn gradient_length_correction_does_not_gain_energy() {
    let gain = free_rod_energy_gain(LengthCorrection::Gradient);
    assert!(gain < 0.01, "gain {:.2}% of released energy", 100.0 * gain);
}

/// Bend and twist as one block ([`rodlab::constraint::BendTwist::Block`]): one application
/// removes `alpha_b` of psi and `alpha_t` of tau together, to first order, even where the
/// chest's principal axes are turned away from the rod frame (so the bend and twist axes are
/// coupled through its inertia); at 0.03-0.05 rad the second-order rest is under 3%.
#[test]
fn the_bend_twist_block_removes_alpha_of_each_angle_at_once() {
    use rodlab::constraint::parts::relative_rotation_block;
    use rodlab::solver::body::SolverBody;
    let (alpha_b, alpha_t) = (0.3, 0.6);
    for tilt in [0.0f32, 0.35, 0.8] {
        let (mut bodies, _) = pelvis_chest();
        // the chest turned about z before the rod is made: its long axis leaves the rod frame's
        let centre = bodies[1].position;
        bodies[1].set_pose(centre, Quat::from_rotation_z(tilt));
        let rod = Rod::instantiate("spine", &bodies, BodyId(0), BodyId(1), Vec3::Z).unwrap();
        let (pivot, chest) = (bodies[1].position, &mut bodies[1]);
        let bend = Quat::from_axis_angle(Vec3::new(1.0, 0.0, 1.0).normalize(), 0.04);
        let twist = Quat::from_rotation_y(0.03);
        chest.set_pose(pivot, bend * twist * chest.orientation);
        let before = rod_state(&rod, &bodies);
        let (fa, fb) = rod.frames(&bodies[0], &bodies[1]);
        let (ta, tb) = (fa * Vec3::X, fb * Vec3::X);
        let axis = ta.cross(tb).normalize();
        let (mut a, mut b) = (
            SolverBody::from_body(&bodies[0]),
            SolverBody::from_body(&bodies[1]),
        );
        let errors = (-alpha_b * before.psi, -alpha_t * before.tau);
        relative_rotation_block(&mut a, &mut b, (axis, tb), errors);
        a.write_pose(&mut bodies[0]);
        b.write_pose(&mut bodies[1]);
        let after = rod_state(&rod, &bodies);
        let (psi_left, tau_left) = (after.psi / before.psi, after.tau / before.tau);
        println!(
            "chest tilted {tilt} rad: psi {:.4} -> {:.4} ({psi_left:.3} left), tau {:.4} -> {:.4} ({tau_left:.3} left)",
            before.psi, after.psi, before.tau, after.tau
        );
        assert!(
            (psi_left - (1.0 - alpha_b)).abs() < 0.03 && (tau_left - (1.0 - alpha_t)).abs() < 0.03,
            "tilt {tilt}: left {psi_left} of psi and {tau_left} of tau, asked {} and {}",
            1.0 - alpha_b,
            1.0 - alpha_t
        );
    }
}
