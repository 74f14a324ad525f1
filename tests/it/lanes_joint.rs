//! The branch-free lane kernel for ball-and-socket joints (`ball_socket_lanes.rs`) against the
//! scalar reference `JointRow::solve`: one batch call gives the poses of W scalar calls.
//!
//! Cases: cheap and exact flavours (pure and mixed batches), with and without limits and
//! springs, lanes whose limits are violated (swing, twist on both sides, twist unwrapped across
//! +-pi), lanes at rest, an antiparallel swing (the fallback axis), and static bodies shared
//! across lanes. W = 4, 8 and 16 (`solve_lanes::<L>`; a width this CPU does not run takes the
//! portable lanes of that width, which compute the same bits).

use rodlab::constraint::ball_socket_lanes::solve_lanes;
use rodlab::constraint::{AngularLimit, AngularSpring, JointFlavour, JointRow};
use rodlab::math::{quat_from_rotation_vector, rotate_by_small, Mat3, Quat, Vec3};
use rodlab::solver::body::{SharedBodies, SolverBody};
use std::f32::consts::PI;

/// xorshift64* with a fixed seed: deterministic, no extra crates.
struct Rng(u64);

impl Rng {
    fn f(&mut self) -> f32 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (x >> 40) as f32 / (1u64 << 24) as f32
    }
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.f()
    }
    fn vec(&mut self, s: f32) -> Vec3 {
        Vec3::new(self.range(-s, s), self.range(-s, s), self.range(-s, s))
    }
    fn quat(&mut self) -> Quat {
        let v = self.vec(1.0).normalize_or(Vec3::X);
        quat_from_rotation_vector(v * self.range(0.0, PI))
    }
}

fn dynamic_body(rng: &mut Rng, position: Vec3) -> SolverBody {
    let predicted = rng.quat();
    let correction = rng.vec(0.05);
    let orientation = rotate_by_small(predicted, correction);
    let mass = rng.range(0.5, 5.0);
    let inertia_diag = Vec3::new(
        rng.range(0.01, 0.2),
        rng.range(0.01, 0.2),
        rng.range(0.01, 0.2),
    );
    let r = Mat3::from_quat(orientation);
    SolverBody {
        orientation,
        predicted,
        position,
        inverse_mass: 1.0 / mass,
        rotation_correction: correction,
        inverse_inertia: r * Mat3::from_diagonal(inertia_diag.recip()) * r.transpose(),
    }
}

fn static_body(rng: &mut Rng) -> SolverBody {
    let orientation = rng.quat();
    SolverBody {
        orientation,
        predicted: orientation,
        position: rng.vec(1.0),
        inverse_mass: 0.0,
        rotation_correction: Vec3::ZERO,
        inverse_inertia: Mat3::ZERO,
    }
}

#[derive(Clone, Copy, Debug)]
enum Case {
    /// Dislocated, nothing else.
    Plain,
    /// With a limit, violated (swing or twist) most of the time.
    Limited,
    /// With a spring.
    Sprung,
    /// Limit and spring.
    Both,
    /// Anchors coincide exactly, identity orientations, limit satisfied: no correction.
    Rest,
    /// Hinge with antiparallel x axes: the swing axis falls back to a perpendicular.
    Antiparallel,
    /// Twist past +-pi since the substep's start: the limit unwraps it.
    Unwrap,
}

/// A joint between bodies `ia` and `ib` (already in `bodies`), set up for `case`.
fn make_row(
    rng: &mut Rng,
    bodies: &mut [SolverBody],
    ia: u32,
    ib: u32,
    case: Case,
    flavour: JointFlavour,
) -> JointRow {
    let mut row = JointRow {
        body_a: ia,
        body_b: ib,
        anchor_a: rng.vec(0.3),
        anchor_b: rng.vec(0.3),
        frame_a: rng.quat(),
        frame_b: rng.quat(),
        limit: None,
        start_twist: 0.0,
        spring: None,
        flavour,
    };
    let limit = AngularLimit::cone(
        rng.range(0.1, 0.6),
        rng.range(-0.8, -0.1),
        rng.range(0.1, 0.8),
    );
    let spring = AngularSpring {
        relaxation: rng.range(0.1, 1.0),
        rest: rng.quat(),
    };
    let start = |rng: &mut Rng, bodies: &[SolverBody], row: &JointRow| {
        // the substep started a little way from the preview
        let qa = rotate_by_small(bodies[ia as usize].orientation, rng.vec(0.2));
        let qb = rotate_by_small(bodies[ib as usize].orientation, rng.vec(0.2));
        AngularLimit::start_twist(qa * row.frame_a, qb * row.frame_b)
    };
    match case {
        Case::Plain => {}
        Case::Limited => {
            row.limit = Some(limit);
            row.start_twist = start(rng, bodies, &row);
        }
        Case::Sprung => row.spring = Some(spring),
        Case::Both => {
            row.limit = Some(limit);
            row.start_twist = start(rng, bodies, &row);
            row.spring = Some(spring);
        }
        Case::Rest => {
            for (i, x) in [(ia, -0.5f32), (ib, 0.5)] {
                let body = &mut bodies[i as usize];
                if body.inverse_mass != 0.0 {
                    body.orientation = Quat::IDENTITY;
                    body.predicted = Quat::IDENTITY;
                    body.rotation_correction = Vec3::ZERO;
                    body.position = Vec3::new(x, 2.0, 1.0);
                }
            }
            let (pa, pb) = (bodies[ia as usize], bodies[ib as usize]);
            let anchor = Vec3::new(0.0, 2.0, 1.0);
            row.anchor_a = pa.orientation.inverse() * (anchor - pa.position);
            row.anchor_b = pb.orientation.inverse() * (anchor - pb.position);
            row.frame_a = pa.orientation.inverse();
            row.frame_b = pb.orientation.inverse();
            row.limit = Some(AngularLimit::cone(0.5, -0.5, 0.5));
            row.spring = Some(AngularSpring {
                relaxation: 0.5,
                rest: pa.orientation.inverse() * pb.orientation,
            });
        }
        Case::Antiparallel => {
            for i in [ia, ib] {
                let body = &mut bodies[i as usize];
                body.orientation = Quat::IDENTITY;
                body.predicted = Quat::IDENTITY;
                body.rotation_correction = Vec3::ZERO;
            }
            row.frame_a = Quat::IDENTITY;
            row.frame_b = Quat::from_xyzw(0.0, 0.0, 1.0, 0.0); // x axis -> -x exactly
            row.limit = Some(AngularLimit::hinge(-0.3, 0.3));
        }
        Case::Unwrap => {
            // relative twist now 3.0 rad about x, at the start -3.0 + ... (just across -pi)
            let qa = bodies[ia as usize].orientation;
            let fa = row.frame_a;
            let fb_world_now = qa * fa * Quat::from_rotation_x(3.0);
            row.frame_b = bodies[ib as usize].orientation.inverse() * fb_world_now;
            row.limit = Some(AngularLimit::cone(1.0, -2.5, 2.9));
            row.start_twist = -3.1;
        }
    }
    row
}

/// Builds W rows over fresh bodies; `statics` puts a shared static body into some lanes.
fn batch(
    seed: u64,
    w: usize,
    cases: &[Case],
    flavours: &[JointFlavour],
    statics: bool,
) -> (Vec<SolverBody>, Vec<JointRow>) {
    let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    let mut bodies = Vec::new();
    bodies.push(static_body(&mut rng)); // body 0, static, shared
    let mut rows = Vec::new();
    for i in 0..w {
        let pa = rng.vec(2.0);
        let dislocation = rng.vec(0.1);
        let a = bodies.len() as u32;
        bodies.push(dynamic_body(&mut rng, pa));
        let b = bodies.len() as u32;
        bodies.push(dynamic_body(
            &mut rng,
            pa + Vec3::new(0.3, 0.0, 0.0) + dislocation,
        ));
        let (ia, ib) = match (statics, i % 4) {
            (true, 1) => (0, b),
            (true, 2) => (a, 0),
            _ => (a, b),
        };
        let case = cases[i % cases.len()];
        let flavour = flavours[i % flavours.len()];
        rows.push((make_row(&mut rng, &mut bodies, ia, ib, case, flavour), case));
    }
    // A static body's anchor is placed next to the dynamic one's (at the final poses: some
    // cases turn the shared static body), so its lanes are as dislocated as the others.
    for (row, case) in &mut rows {
        let static_a = row.body_a == 0;
        if !static_a && row.body_b != 0 {
            continue;
        }
        let (s, k) = if static_a {
            (row.body_a, row.body_b)
        } else {
            (row.body_b, row.body_a)
        };
        let (s, k) = (bodies[s as usize], bodies[k as usize]);
        let (anchor_k, frame_k) = if static_a {
            (row.anchor_b, row.frame_b)
        } else {
            (row.anchor_a, row.frame_a)
        };
        let rest = matches!(case, Case::Rest);
        let target = k.point(anchor_k) + if rest { Vec3::ZERO } else { rng.vec(0.05) };
        let anchor_s = s.orientation.inverse() * (target - s.position);
        if static_a {
            row.anchor_a = anchor_s;
        } else {
            row.anchor_b = anchor_s;
        }
        if rest {
            let frame_s = s.orientation.inverse() * (k.orientation * frame_k);
            let (qa, qb) = if static_a {
                (s.orientation, k.orientation)
            } else {
                (k.orientation, s.orientation)
            };
            if static_a {
                row.frame_a = frame_s;
            } else {
                row.frame_b = frame_s;
            }
            row.spring.as_mut().unwrap().rest = qa.inverse() * qb;
        }
    }
    (bodies, rows.into_iter().map(|(row, _)| row).collect())
}

/// Largest (position, orientation component) difference between the scalar solve and the
/// lane kernel `kernel` on the same rows.
fn compare(
    bodies: &[SolverBody],
    rows: &[JointRow],
    kernel: fn(&mut [JointRow], SharedBodies),
    iterations: usize,
) -> (f32, f32) {
    let mut scalar = bodies.to_vec();
    let mut lanes = bodies.to_vec();
    let mut lane_rows = rows.to_vec();
    for _ in 0..iterations {
        let shared = SharedBodies::new(&mut scalar);
        for row in rows {
            unsafe { shared.with_pair(row.body_a, row.body_b, |a, b| row.solve(a, b)) };
        }
        kernel(&mut lane_rows, SharedBodies::new(&mut lanes));
    }
    let mut dp = 0.0f32;
    let mut dq = 0.0f32;
    for (i, (s, l)) in scalar.iter().zip(&lanes).enumerate() {
        assert!(
            l.position.is_finite() && l.orientation.is_finite(),
            "body {i} not finite"
        );
        dp = dp.max((s.position - l.position).abs().max_element());
        dq = dq.max((Vec4(s.orientation) - Vec4(l.orientation)).max_abs());
        dq = dq.max(
            (s.rotation_correction - l.rotation_correction)
                .abs()
                .max_element(),
        );
        if s.inverse_mass == 0.0 {
            assert_eq!(s.position, bodies[i].position);
            assert_eq!(l.position, bodies[i].position, "static body {i} moved");
            assert_eq!(
                l.orientation, bodies[i].orientation,
                "static body {i} turned"
            );
        }
    }
    (dp, dq)
}

struct Vec4(Quat);
impl std::ops::Sub for Vec4 {
    type Output = glam::Vec4;
    fn sub(self, o: Self) -> glam::Vec4 {
        glam::Vec4::from(self.0) - glam::Vec4::from(o.0)
    }
}
trait MaxAbs {
    fn max_abs(self) -> f32;
}
impl MaxAbs for glam::Vec4 {
    fn max_abs(self) -> f32 {
        self.abs().max_element()
    }
}

const POSITION_TOL: f32 = 1e-5;
const ORIENTATION_TOL: f32 = 1e-4;

fn lanes4(rows: &mut [JointRow], bodies: SharedBodies) {
    at_width!(4, solve_lanes(rows, bodies))
}
fn lanes8(rows: &mut [JointRow], bodies: SharedBodies) {
    at_width!(8, solve_lanes(rows, bodies))
}
fn lanes16(rows: &mut [JointRow], bodies: SharedBodies) {
    at_width!(16, solve_lanes(rows, bodies))
}

const ALL: [Case; 7] = [
    Case::Plain,
    Case::Limited,
    Case::Sprung,
    Case::Both,
    Case::Rest,
    Case::Antiparallel,
    Case::Unwrap,
];

fn sweep(w: usize, kernel: fn(&mut [JointRow], SharedBodies), statics: bool) -> (f32, f32) {
    use JointFlavour::{Cheap, Exact};
    let flavour_sets: [&[JointFlavour]; 3] = [&[Cheap], &[Exact], &[Exact, Cheap, Cheap]];
    let case_sets: Vec<Vec<Case>> = vec![
        ALL.to_vec(),
        vec![Case::Plain],
        vec![Case::Limited],
        vec![Case::Sprung],
        vec![Case::Rest],
        vec![Case::Unwrap, Case::Plain],
        vec![Case::Antiparallel, Case::Limited, Case::Rest],
    ];
    let (mut dp, mut dq) = (0.0f32, 0.0f32);
    for seed in 0..40u64 {
        for flavours in flavour_sets {
            for (k, cases) in case_sets.iter().enumerate() {
                // rotate the case list so every case meets every lane
                let mut cases = cases.clone();
                let n = cases.len();
                cases.rotate_left(seed as usize % n);
                let (bodies, rows) = batch(seed * 31 + k as u64, w, &cases, flavours, statics);
                let (p, q) = compare(&bodies, &rows, kernel, 1);
                assert!(
                    p < POSITION_TOL && q < ORIENTATION_TOL,
                    "seed {seed}, cases {cases:?}, flavours {flavours:?}: position {p:e}, orientation {q:e}"
                );
                dp = dp.max(p);
                dq = dq.max(q);
            }
        }
    }
    println!("W={w} statics={statics}: max |dp| {dp:e}, max |dq| {dq:e}");
    (dp, dq)
}

#[test]
fn four_lanes_match_scalar() {
    sweep(4, lanes4, false);
}

#[test]
fn four_lanes_with_static_bodies_match_scalar() {
    sweep(4, lanes4, true);
}

#[test]
fn eight_lanes_match_scalar() {
    sweep(8, lanes8, false);
    sweep(8, lanes8, true);
}

#[test]
fn sixteen_lanes_match_scalar() {
    sweep(16, lanes16, false);
    sweep(16, lanes16, true);
}

/// A colour's last batch has fewer rows than lanes: the empty lanes repeat the first row, and
/// the rows come out as the scalar solve leaves them.
#[test]
fn padded_batches_match_scalar() {
    sweep(11, lanes16, true);
    sweep(5, lanes8, false);
    sweep(1, lanes8, false);
}

/// The lanes at rest stay exactly where they are; the antiparallel hinge is corrected.
#[test]
fn rest_lanes_do_not_move_and_fallback_axis_works() {
    let (bodies, rows) = batch(
        7,
        4,
        &[Case::Rest, Case::Antiparallel],
        &[JointFlavour::Exact],
        false,
    );
    let mut lanes = bodies.clone();
    let mut lane_rows = rows.clone();
    lanes4(&mut lane_rows, SharedBodies::new(&mut lanes));
    for (row, case) in rows.iter().zip([
        Case::Rest,
        Case::Antiparallel,
        Case::Rest,
        Case::Antiparallel,
    ]) {
        let (a, b) = (row.body_a as usize, row.body_b as usize);
        match case {
            Case::Rest => {
                for i in [a, b] {
                    assert_eq!(lanes[i].position, bodies[i].position);
                    assert_eq!(lanes[i].orientation, bodies[i].orientation);
                }
            }
            _ => {
                // swing reduced from pi
                let ax = lanes[a].orientation * row.frame_a * Vec3::X;
                let bx = lanes[b].orientation * row.frame_b * Vec3::X;
                assert!(
                    ax.dot(bx) > -0.99,
                    "antiparallel hinge not turned: {}",
                    ax.dot(bx)
                );
            }
        }
    }
    let (p, q) = compare(&bodies, &rows, lanes4, 1);
    assert!(p < POSITION_TOL && q < ORIENTATION_TOL, "{p:e} {q:e}");
}

/// Several iterations in a row stay together too (errors do not grow).
#[test]
fn iterations_stay_together() {
    for seed in 0..20 {
        for flavours in [&[JointFlavour::Cheap][..], &[JointFlavour::Exact][..]] {
            let (bodies, rows) = batch(1000 + seed, 4, &ALL, flavours, seed % 2 == 0);
            let (p, q) = compare(&bodies, &rows, lanes4, 10);
            assert!(
                p < POSITION_TOL && q < ORIENTATION_TOL,
                "seed {seed}: {p:e} {q:e}"
            );
            let (bodies, rows) = batch(2000 + seed, 8, &ALL, flavours, seed % 2 == 0);
            let (p, q) = compare(&bodies, &rows, lanes8, 10);
            assert!(
                p < POSITION_TOL && q < ORIENTATION_TOL,
                "seed {seed}: {p:e} {q:e}"
            );
        }
    }
}

/// Sixteen chains of four links, spun and pushed at random, some joints limited and some
/// sprung: three frames of the whole world's step agree between the row solvers within 1e-4 m
/// and 3e-3 in each quaternion component (the lanes' atan2 and sin_cos round otherwise than
/// libm's, and a limit reached a substep apart turns a link by a few thousandths: measured
/// 5.6e-5 m and 2.2e-3 cheap).
#[test]
fn world_steps_agree_scalar_and_simd() {
    const FRAMES: usize = 3;
    use rodlab::body::{Body, BodyKind};
    use rodlab::constraint::BallSocket;
    use rodlab::shape::{Axis, Shape};
    use rodlab::world::{Settings, SolverKind, World};
    let build = |solver: SolverKind, flavour: JointFlavour| {
        let mut world = World::new(Settings {
            solver,
            iterations: 10,
            ..Settings::default()
        });
        let mut rng = Rng(77);
        for c in 0..16 {
            let top = Vec3::new(c as f32, 3.0, 0.0);
            let mut previous = world.add_body(
                Body::new(
                    format!("s{c}"),
                    BodyKind::Fixed,
                    Shape::Sphere { radius: 0.03 },
                    1.0,
                )
                .with_pose(top, Quat::IDENTITY),
            );
            for i in 0..4 {
                let centre = top - Vec3::Y * (0.1 * (2 * i + 1) as f32);
                let mut body = Body::new(
                    format!("l{c}_{i}"),
                    BodyKind::Dynamic,
                    Shape::Capsule {
                        half_height: 0.1,
                        radius: 0.03,
                        axis: Axis::Y,
                    },
                    1.0,
                )
                .with_pose(centre, Quat::IDENTITY);
                body.linear_velocity = rng.vec(1.0);
                body.angular_velocity = rng.vec(6.0);
                let link = world.add_body(body);
                let mut joint = BallSocket::at_world_anchor(
                    format!("j{c}_{i}"),
                    &world.bodies,
                    previous,
                    link,
                    centre + Vec3::Y * 0.1,
                    Quat::from_rotation_z(-std::f32::consts::FRAC_PI_2),
                )
                .with_flavour(flavour);
                if (c + i) % 2 == 0 {
                    joint = joint.with_limit(AngularLimit::cone(0.4, -0.3, 0.3));
                }
                if (c + i) % 3 == 0 {
                    joint = joint.with_spring(&world.bodies, 0.2);
                }
                world.add_constraint(joint);
                previous = link;
            }
        }
        world
    };
    for flavour in [JointFlavour::Cheap, JointFlavour::Exact] {
        let mut scalar = build(SolverKind::Scalar, flavour);
        let mut simd = build(SolverKind::Simd, flavour);

        let mut worst = (0.0f32, 0.0f32);
        for _ in 0..FRAMES {
            scalar.step().unwrap();
            simd.step().unwrap();
            for (s, l) in scalar.bodies.iter().zip(&simd.bodies) {
                worst.0 = worst.0.max((s.position - l.position).abs().max_element());
                worst.1 = worst
                    .1
                    .max((Vec4(s.orientation) - Vec4(l.orientation)).max_abs());
            }
        }
        println!(
            "world {flavour}: {FRAMES} frames, max |dp| {:e}, max |dq| {:e}",
            worst.0, worst.1
        );
        assert!(worst.0 < 1e-4 && worst.1 < 3e-3, "{flavour}: {worst:?}");
    }
}
