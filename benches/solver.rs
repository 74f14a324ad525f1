//! Criterion benchmarks: ns per constraint solve, scalar and SIMD (W = 4, 8 and 16 where the CPU
//! runs them, from lanes packed as the SIMD solver packs them once a substep), for ball-and-socket joints (cheap,
//! exact, exact with limits), the rod (bend, twist, curve and length in one function) and
//! contact points, 64 independent constraints a batch; then one passive-bending step per
//! spine. After criterion's report, a summary table with the cost of packing and the rod/cheap
//! ratio per solver.
//! Run with `cargo bench --bench solver`.

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use rodlab::body::{Body, BodyId, BodyKind};
use rodlab::constraint::{
    AngularLimit, BallSocket, BendTwist, JointFlavour, JointRow, Rod, RodRow,
};
use rodlab::contact::{ContactPoint, Contacts, Softness, Stacking};
use rodlab::lanes::{F32x16, F32x4, F32x8, Lane, LaneWidth, LaneWork};
use rodlab::math::{Quat, Vec3};
use rodlab::ragdoll::SpineKind;
use rodlab::scene::Scene;
use rodlab::shape::{Axis, Shape};
use rodlab::sim::{self, NoObserver, Overrides};
use rodlab::solver::body::{pair_mut, SharedBodies, SolverBody};
use rodlab::solver::packed::LaneRows;
use rodlab::solver::ScalarRows;
use std::time::Instant;

const COUNT: usize = 64;

fn capsule(name: String, mass: f32, radius: f32) -> Body {
    let shape = Shape::Capsule {
        half_height: 0.08,
        radius,
        axis: Axis::Y,
    };
    Body::new(name, BodyKind::Dynamic, shape, mass)
}

/// `COUNT` independent pairs of capsules joined at a shared anchor, each pair then displaced
/// and turned off its joint (and past its limits), so every solve does real work.
fn dislocated_joints(flavour: JointFlavour, limits: bool) -> (Vec<SolverBody>, Vec<JointRow>) {
    let mut bodies = Vec::new();
    let mut rows = Vec::new();
    for i in 0..COUNT {
        let x = i as f32;
        bodies.push(
            capsule(format!("a{i}"), 1.0, 0.03).with_pose(Vec3::new(x, 0.0, 0.0), Quat::IDENTITY),
        );
        bodies.push(
            capsule(format!("b{i}"), 1.0, 0.03).with_pose(Vec3::new(x, -0.2, 0.0), Quat::IDENTITY),
        );
        let frame = Quat::from_rotation_z(-std::f32::consts::FRAC_PI_2);
        let ids = (BodyId(2 * i as u32), BodyId(2 * i as u32 + 1));
        let anchor = Vec3::new(x, -0.1, 0.0);
        let mut joint =
            BallSocket::at_world_anchor(format!("j{i}"), &bodies, ids.0, ids.1, anchor, frame)
                .with_flavour(flavour);
        if limits {
            joint = joint.with_limit(AngularLimit::cone(0.3, -0.2, 0.2));
        }
        let mut row = joint.prepare();
        let wobble = (x * 1.7).sin();
        let b = &mut bodies[2 * i + 1];
        let position = b.position + Vec3::new(0.02 * wobble, 0.01, -0.015 * wobble);
        b.set_pose(
            position,
            Quat::from_rotation_z(0.5 * wobble) * Quat::from_rotation_x(0.3),
        );
        row.begin_substep(&bodies);
        rows.push(row);
    }
    (bodies.iter().map(SolverBody::from_body).collect(), rows)
}

/// `COUNT` independent pelvis-chest pairs joined by rods, each bent, twisted and stretched off
/// its rest state.
fn perturbed_rods(bend_twist: BendTwist) -> (Vec<SolverBody>, Vec<RodRow>) {
    let mut bodies = Vec::new();
    let mut rows = Vec::new();
    for i in 0..COUNT {
        let x = i as f32;
        bodies.push(
            capsule(format!("p{i}"), 14.5, 0.1).with_pose(Vec3::new(x, 1.0, 0.0), Quat::IDENTITY),
        );
        bodies.push(
            capsule(format!("c{i}"), 18.1, 0.12)
                .with_pose(Vec3::new(x, 1.385, 0.0), Quat::IDENTITY),
        );
        let ids = (BodyId(2 * i as u32), BodyId(2 * i as u32 + 1));
        let mut rod = Rod::instantiate(format!("r{i}"), &bodies, ids.0, ids.1, Vec3::Z).unwrap();
        rod.params.alpha_bend = 0.1;
        rod.params.alpha_twist = 0.5;
        rod.params.bend_twist = bend_twist;
        rows.push(rod.prepare());
        let wobble = (x * 1.7).sin();
        let chest = &mut bodies[2 * i + 1];
        let pose = chest.position + Vec3::new(0.01 * wobble, -0.02, 0.05);
        chest.set_pose(
            pose,
            Quat::from_rotation_x(0.4 + 0.1 * wobble) * Quat::from_rotation_y(0.2),
        );
    }
    (bodies.iter().map(SolverBody::from_body).collect(), rows)
}

/// `COUNT` independent contact points: pairs of crossing capsules (limb-sized, of different
/// masses), each pair pressed 1 cm into the other and sliding a little, found by the narrow
/// phase as the solver finds them, then a first iteration run so every point has pushed and
/// its friction works (sticking and sliding lanes).
fn pressed_contacts() -> (Vec<SolverBody>, Vec<ContactPoint>) {
    let mut bodies = Vec::new();
    for i in 0..COUNT {
        let x = 2.0 * i as f32;
        let wobble = (i as f32 * 1.7).sin();
        let lower = capsule(format!("l{i}"), 4.0 + wobble, 0.05).with_pose(
            Vec3::new(x, 0.0, 0.0),
            Quat::from_rotation_z(std::f32::consts::FRAC_PI_2),
        );
        let mut upper = capsule(format!("u{i}"), 2.0, 0.04).with_pose(
            Vec3::new(x + 0.01 * wobble, 0.08, 0.0),
            Quat::from_rotation_x(std::f32::consts::FRAC_PI_2 + 0.2 * wobble),
        );
        upper.linear_velocity = Vec3::new(0.3 * wobble, -0.5, 0.2);
        upper.static_friction = 0.6 + 0.2 * wobble;
        upper.dynamic_friction = 0.4 + 0.1 * wobble;
        bodies.push(lower);
        bodies.push(upper);
    }
    let mut contacts = Contacts::default();
    contacts.detect(&bodies, &Default::default(), 1.0 / 60.0, 0.02);
    let (soft, stacking) = (Softness::default(), Stacking::default());
    contacts.begin_substep(&bodies, 1.0 / 60.0, f32::INFINITY, soft, stacking);
    let mut points = contacts.points.clone();
    assert_eq!(points.len(), COUNT, "one point per crossing pair");
    let mut solver: Vec<SolverBody> = bodies.iter().map(SolverBody::from_body).collect();
    for (i, body) in solver.iter_mut().enumerate().filter(|(i, _)| i % 2 == 1) {
        let wobble = (i as f32 * 0.9).sin();
        body.position += Vec3::new(0.01 * wobble, -0.01, 0.005);
    }
    for p in &mut points {
        let (a, b) = pair_mut(&mut solver, p.body_a.index(), p.body_b.index());
        p.solve(a, b);
    }
    (solver, points)
}

#[derive(Clone, Copy, PartialEq)]
enum Width {
    Scalar,
    W4,
    W8,
    W16,
}

const WIDTHS: [(&str, Width); 4] = [
    ("scalar", Width::Scalar),
    ("simd4", Width::W4),
    ("simd8", Width::W8),
    ("simd16", Width::W16),
];

/// One kind's rows and, as the SIMD solver keeps them, packed into 4, 8 and 16 lanes.
#[derive(Clone)]
struct Packed<T: LaneRows> {
    bodies: Vec<SolverBody>,
    rows: Vec<T>,
    w4: Vec<T::Lanes<F32x4>>,
    w8: Vec<T::Lanes<F32x8>>,
    w16: Vec<T::Lanes<F32x16>>,
}

impl<T: LaneRows + Clone> Packed<T> {
    fn new((bodies, rows): (Vec<SolverBody>, Vec<T>)) -> Self {
        Packed {
            w4: rows.chunks_exact(4).map(T::pack).collect(),
            w8: rows.chunks_exact(8).map(T::pack).collect(),
            w16: rows.chunks_exact(16).map(T::pack).collect(),
            bodies,
            rows,
        }
    }

    /// Packs the rows into the existing batches of the widest lanes this CPU runs again (no
    /// allocation in the timing).
    fn repack(&mut self) {
        match LaneWidth::detect() {
            LaneWidth::W4 => F32x4::dispatch(Repack::<T, F32x4>(&mut self.w4, &self.rows)),
            LaneWidth::W8 => F32x8::dispatch(Repack::<T, F32x8>(&mut self.w8, &self.rows)),
            LaneWidth::W16 => F32x16::dispatch(Repack::<T, F32x16>(&mut self.w16, &self.rows)),
        }
    }

    /// One solve of every row: scalar from the rows, or from the packed lanes.
    fn solve(&mut self, width: Width) {
        let shared = SharedBodies::new(&mut self.bodies);
        match width {
            Width::Scalar => {
                // the scalar kernel as the solver runs it, in the dispatched function
                let rows = &mut self.rows[..];
                let width = LaneWidth::detect();
                rodlab::with_lane_type!(width, L => L::dispatch(ScalarRows { rows, bodies: shared }))
            }
            Width::W4 => F32x4::dispatch(SolveBatches::<T, F32x4>(&mut self.w4, shared)),
            Width::W8 => F32x8::dispatch(SolveBatches::<T, F32x8>(&mut self.w8, shared)),
            Width::W16 => F32x16::dispatch(SolveBatches::<T, F32x16>(&mut self.w16, shared)),
        }
    }
}

impl Width {
    /// Whether this CPU runs the width (the scalar solver always).
    fn runs(self) -> bool {
        match self {
            Width::Scalar | Width::W4 => true,
            Width::W8 => LaneWidth::W8.is_available(),
            Width::W16 => LaneWidth::W16.is_available(),
        }
    }
}

/// One solve of every batch, in the function compiled for the lane type's instructions (as
/// the solver runs its colours: `rodlab::lanes::Lane::dispatch`).
struct SolveBatches<'a, T: LaneRows, L: Lane>(&'a mut [T::Lanes<L>], SharedBodies);

impl<T: LaneRows, L: Lane> LaneWork<L> for SolveBatches<'_, T, L> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        // (a loop, not a closure: a closure's body would compile outside the function)
        for batch in self.0.iter_mut() {
            T::solve_lanes(batch, self.1);
        }
    }
}

/// Every batch packed again from its rows, as the solver packs, in the dispatched function.
struct Repack<'a, T: LaneRows, L: Lane>(&'a mut [T::Lanes<L>], &'a [T]);

impl<T: LaneRows, L: Lane> LaneWork<L> for Repack<'_, T, L> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        for (lanes, rows) in self.0.iter_mut().zip(self.1.chunks(L::W)) {
            *lanes = T::pack(rows);
        }
    }
}

/// One benchmarked batch: `COUNT` independent constraints of one kind and their bodies.
#[derive(Clone)]
enum Batch {
    Joints(Packed<JointRow>),
    Rods(Packed<RodRow>),
    Contacts(Packed<ContactPoint>),
}

/// The benchmarked kinds.
#[derive(Clone, Copy)]
enum Case {
    Joint(JointFlavour, bool),
    Rod(BendTwist),
    Contact,
}

impl Batch {
    fn new(case: Case) -> Self {
        match case {
            Case::Joint(flavour, limits) => {
                Batch::Joints(Packed::new(dislocated_joints(flavour, limits)))
            }
            Case::Rod(bend_twist) => Batch::Rods(Packed::new(perturbed_rods(bend_twist))),
            Case::Contact => Batch::Contacts(Packed::new(pressed_contacts())),
        }
    }

    fn solve(&mut self, width: Width) {
        match self {
            Batch::Joints(p) => p.solve(width),
            Batch::Rods(p) => p.solve(width),
            Batch::Contacts(p) => p.solve(width),
        }
    }

    /// Packs every row into the widest lanes this CPU runs again (what the SIMD solver does
    /// once a substep).
    fn pack(&mut self) {
        match self {
            Batch::Joints(p) => p.repack(),
            Batch::Rods(p) => p.repack(),
            Batch::Contacts(p) => p.repack(),
        }
    }
}

/// The benchmarked kinds, by label.
fn cases() -> Vec<(&'static str, Case)> {
    vec![
        ("cheap", Case::Joint(JointFlavour::Cheap, false)),
        ("exact", Case::Joint(JointFlavour::Exact, false)),
        ("exact_with_limits", Case::Joint(JointFlavour::Exact, true)),
        ("rod", Case::Rod(BendTwist::Sequential)),
        ("rod_block", Case::Rod(BendTwist::Block)),
        ("contact", Case::Contact),
    ]
}

fn constraint_solves(c: &mut Criterion) {
    let mut group = c.benchmark_group("constraint_solve");
    group.throughput(Throughput::Elements(COUNT as u64));
    for (label, case) in cases() {
        let batch = Batch::new(case);
        for (solver, width) in WIDTHS.into_iter().filter(|(_, w)| w.runs()) {
            group.bench_function(format!("{label}/{solver}"), |b| {
                b.iter_batched_ref(
                    || batch.clone(),
                    |batch| batch.solve(width),
                    BatchSize::SmallInput,
                )
            });
        }
    }
    group.finish();
    summary();
}

/// ns per constraint: the fastest of many timed rounds of 64 solves (each on a fresh copy).
fn ns_per_solve(mut round: impl FnMut() -> std::time::Duration) -> f64 {
    (0..2000).map(|_| round()).min().unwrap().as_nanos() as f64 / COUNT as f64
}

/// The side-by-side table the issue asks for: scalar and SIMD per kind (a solve from packed
/// lanes, as every iteration of the SIMD solver runs it), what packing costs once a substep,
/// and rod/cheap.
fn summary() {
    let widest = LaneWidth::detect().lanes();
    println!(
        "\nns per constraint (fastest of 2000 rounds of {COUNT}), machine: {}; the SIMD solver \
         runs {widest} lanes here (a width this CPU does not run: NaN)",
        rodlab::machine::name(),
    );
    println!(
        "{:<20} {:>8} {:>8} {:>8} {:>8} {:>8}",
        "kind",
        "scalar",
        "simd4",
        "simd8",
        "simd16",
        format!("pack{widest}")
    );
    let mut table = Vec::new();
    for (label, case) in cases() {
        let batch = Batch::new(case);
        let timed = |f: &dyn Fn(&mut Batch)| {
            ns_per_solve(|| {
                let mut fresh = batch.clone();
                let start = Instant::now();
                f(&mut fresh);
                let time = start.elapsed();
                std::hint::black_box(&fresh);
                time
            })
        };
        let mut row: Vec<f64> = WIDTHS
            .iter()
            .map(|&(_, w)| match w.runs() {
                true => timed(&|b| b.solve(w)),
                false => f64::NAN,
            })
            .collect();
        row.push(timed(&|b| b.pack()));
        println!(
            "{:<20} {:>8.1} {:>8.1} {:>8.1} {:>8.1} {:>8.1}",
            label, row[0], row[1], row[2], row[3], row[4]
        );
        table.push(row);
    }
    let cheap = &table[0];
    for (label, rod) in [("rod", &table[3]), ("rod_block", &table[4])] {
        println!(
            "{label}/cheap: scalar {:.2}, simd4 {:.2}, simd8 {:.2}, simd16 {:.2} (paper §7: 60/20 = 3)",
            rod[0] / cheap[0],
            rod[1] / cheap[1],
            rod[2] / cheap[2],
            rod[3] / cheap[3]
        );
    }
    let speedup: Vec<String> = (cases().iter().zip(&table))
        .map(|((label, _), t)| {
            let x = |i: usize| t[0] / t[i];
            format!("{label} {:.2}x/{:.2}x/{:.2}x", x(1), x(2), x(3))
        })
        .collect();
    println!(
        "simd speed-up over scalar (W=4/8/16): {}; packing is paid once a substep, the solve \
         every iteration\n",
        speedup.join(", ")
    );
}

/// One 20-iteration step of the passive-bending scene with both ragdolls given one spine.
fn passive_bending_step(c: &mut Criterion) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/passive_bending.toml");
    let scene = Scene::load(path).unwrap();
    let mut group = c.benchmark_group("passive_bending_step");
    for (label, spine, flavour) in [
        ("chain3_cheap", SpineKind::Chain3, JointFlavour::Cheap),
        ("chain3_exact", SpineKind::Chain3, JointFlavour::Exact),
        ("rod_cheap_limbs", SpineKind::Rod, JointFlavour::Cheap),
    ] {
        let mut variant = scene.clone();
        Overrides {
            spine: Some(spine),
            joint_flavour: Some(flavour),
            ..Default::default()
        }
        .apply(&mut variant.def);
        let mut lab = variant.build().unwrap();
        sim::run(&mut lab, 30, &mut NoObserver).unwrap(); // get it moving
        let world = lab.world;
        group.bench_function(label, |b| {
            b.iter_batched_ref(
                || world.clone(),
                |w| w.step().unwrap(),
                BatchSize::SmallInput,
            )
        });
    }
    group.finish();
}

criterion_group!(benches, constraint_solves, passive_bending_step);
criterion_main!(benches);
