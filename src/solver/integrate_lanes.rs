//! Steps 3.1, 3.2 and 3.4 for W bodies at once, for [`SolverKind::Simd`](super::SolverKind):
//! [`integrate_velocity`], [`predict_pose`] and [`commit_pose`] of `integrate.rs` on lanes, one
//! body per lane. The maths is the scalar code's, branch-free: the gyroscopic update's Newton
//! step solves its 3x3 system by Cramer's rule, its fixed-point passes run while any lane has
//! not stopped, and the exponential and logarithm maps use the lanes' `sin_cos` and `atan2`.
//!
//! In the 1000-ragdoll rain the per-body passes were a fifth of the frame (the gyroscopic
//! update, the exponential map and the world inertia at about 100 ns a body and substep, the
//! logarithm map of the commit about 60). Fixed, kinematic and sleeping bodies run the scalar
//! code, body by body, so no body's result depends on the batch it shares.
//!
//! [`integrate_velocity`]: super::integrate::integrate_velocity
//! [`predict_pose`]: super::integrate::predict_pose
//! [`commit_pose`]: super::integrate::commit_pose

use super::body::SolverBody;
use super::integrate::{commit_pose, integrate_velocity, predict_pose, GYROSCOPIC_PASSES};
use super::Settings;
use crate::body::{Body, BodyKind};
use crate::lanes::{not, Lane, LaneWidth, LaneWork, MAX_LANES, Q, V3};
use crate::math::{Mat3, Vec3};
use crate::with_lane_type;

/// Whether the lanes may take `body`: the others run the scalar code, body by body.
fn plain(body: &Body) -> bool {
    body.kind == BodyKind::Dynamic && !body.asleep
}

/// Steps 3.1-3.2 for every body, `width` lanes at a time.
pub(super) fn predict(
    width: LaneWidth,
    bodies: &mut [Body],
    hot: &mut [SolverBody],
    settings: &Settings,
    h: f32,
) {
    struct Predict<'a> {
        bodies: &'a mut [Body],
        hot: &'a mut [SolverBody],
        settings: &'a Settings,
        h: f32,
    }
    impl<L: Lane> LaneWork<L> for Predict<'_> {
        type Output = ();
        #[inline(always)]
        fn run(self) {
            let batches = self.bodies.chunks_mut(L::W).zip(self.hot.chunks_mut(L::W));
            for (bodies, hot) in batches {
                predict_batch::<L>(bodies, hot, self.settings, self.h);
            }
        }
    }
    let work = Predict {
        bodies,
        hot,
        settings,
        h,
    };
    with_lane_type!(width, L => L::dispatch(work))
}

/// Step 3.4 for every body, `width` lanes at a time.
pub(super) fn commit(width: LaneWidth, bodies: &mut [Body], hot: &[SolverBody], h: f32) {
    struct Commit<'a> {
        bodies: &'a mut [Body],
        hot: &'a [SolverBody],
        h: f32,
    }
    impl<L: Lane> LaneWork<L> for Commit<'_> {
        type Output = ();
        #[inline(always)]
        fn run(self) {
            let batches = self.bodies.chunks_mut(L::W).zip(self.hot.chunks(L::W));
            for (bodies, hot) in batches {
                commit_batch::<L>(bodies, hot, self.h);
            }
        }
    }
    with_lane_type!(width, L => L::dispatch(Commit { bodies, hot, h }))
}

/// Steps 3.1-3.2 for one to `L::W` bodies: velocities, then the preview poses into `hot`. Each
/// body the lanes may not take runs the scalar code, so a body's result does not depend on
/// the batch it is in.
#[inline(always)]
pub(super) fn predict_batch<L: Lane>(
    bodies: &mut [Body],
    hot: &mut [SolverBody],
    settings: &Settings,
    h: f32,
) {
    for (body, hot) in bodies.iter_mut().zip(hot.iter_mut()) {
        if !plain(body) {
            integrate_velocity(body, settings, h);
            *hot = predict_pose(body, h);
        }
    }
    if !bodies.iter().any(plain) {
        return;
    }
    let n = bodies.len();
    let body = |i: usize| &bodies[if i < n { i } else { 0 }];
    let orientation = Q::<L>::from_fn(|i| body(i).orientation);
    let position = V3::<L>::from_fn(|i| body(i).position);
    let inverse_mass = L::from_fn(|i| body(i).inverse_mass);
    let force = V3::<L>::from_fn(|i| body(i).external_force);
    let inertia = V3::<L>::from_fn(|i| body(i).inertia);
    let inverse_inertia = V3::<L>::from_fn(|i| body(i).inverse_inertia_body);
    let mut velocity = V3::<L>::from_fn(|i| body(i).linear_velocity);
    let angular = V3::<L>::from_fn(|i| body(i).angular_velocity);

    // 3.1 gravity and force, the gyroscopic term, damping, the speed limit
    let hl = L::splat(h);
    velocity = velocity + (V3::splat(settings.gravity) + force.scale(inverse_mass)).scale(hl);
    let converged = if settings.substeps > 1 { 1e-6 } else { 0.0 };
    let mut angular =
        gyroscopic_update(orientation, angular, inertia, inverse_inertia, h, converged)
            .scale(L::splat(1.0) / L::splat(1.0 + h * settings.angular_damping));
    velocity = velocity.scale(L::splat(1.0) / L::splat(1.0 + h * settings.linear_damping));
    let spin = angular.length();
    let limit = L::splat(settings.angular_speed_limit);
    let over = spin.gt(limit);
    angular =
        angular.scale(over.select(limit / spin.max(L::splat(f32::MIN_POSITIVE)), L::splat(1.0)));

    // 3.2 the preview pose and its world inverse inertia
    let predicted_position = position + velocity.scale(hl);
    let predicted = exp(angular.scale(hl)).mul(orientation).normalize();
    let world_inverse_inertia = world_inertia(predicted, inverse_inertia);
    for i in 0..n {
        let body = &mut bodies[i];
        if !plain(body) {
            continue;
        }
        body.linear_velocity = velocity.lane(i);
        body.angular_velocity = angular.lane(i);
        let q = predicted.lane(i);
        hot[i] = SolverBody {
            orientation: q,
            predicted: q,
            position: predicted_position.lane(i),
            inverse_mass: body.inverse_mass,
            rotation_correction: Vec3::ZERO,
            inverse_inertia: world_inverse_inertia[i],
        };
    }
}

/// Step 3.4 for one to `L::W` bodies: velocities from the corrected previews, then the poses
/// (the bodies the lanes may not take by the scalar code, as in [`predict_batch`]).
#[inline(always)]
pub(super) fn commit_batch<L: Lane>(bodies: &mut [Body], hot: &[SolverBody], h: f32) {
    for (body, hot) in bodies.iter_mut().zip(hot) {
        if !plain(body) {
            commit_pose(body, hot, h);
        }
    }
    if !bodies.iter().any(plain) {
        return;
    }
    let n = bodies.len();
    let lane = |i: usize| if i < n { i } else { 0 };
    let before = Q::<L>::from_fn(|i| bodies[lane(i)].orientation);
    let position = V3::<L>::from_fn(|i| bodies[lane(i)].position);
    let after = Q::<L>::from_fn(|i| hot[lane(i)].orientation);
    let moved_to = V3::<L>::from_fn(|i| hot[lane(i)].position);
    let inverse_inertia = V3::<L>::from_fn(|i| bodies[lane(i)].inverse_inertia_body);
    let inverse_h = L::splat(1.0 / h);
    let velocity = (moved_to - position).scale(inverse_h);
    let angular = after
        .mul(before.conjugate())
        .rotation_vector()
        .scale(inverse_h);
    let world_inverse_inertia = world_inertia(after, inverse_inertia);
    for (i, body) in bodies.iter_mut().enumerate().filter(|(_, b)| plain(b)) {
        let (p, q) = (hot[i].position, hot[i].orientation);
        body.linear_velocity = velocity.lane(i);
        body.angular_velocity = angular.lane(i);
        body.position = p;
        body.orientation = q;
        body.inverse_inertia_world = world_inverse_inertia[i];
    }
}

/// [`super::integrate::gyroscopic_update`] per lane: the implicit Newton step, then up to
/// [`GYROSCOPIC_PASSES`] fixed-point passes while any lane has not converged; a lane whose
/// passes stop contracting keeps its Newton step, and a lane whose Jacobian is singular keeps
/// its velocity. Returns the world angular velocity.
#[inline(always)]
fn gyroscopic_update<L: Lane>(
    q: Q<L>,
    angular: V3<L>,
    inertia: V3<L>,
    inverse_inertia: V3<L>,
    h: f32,
    converged: f32,
) -> V3<L> {
    let hl = L::splat(h);
    let w = q.conjugate().rotate(angular);
    let momentum = mul(inertia, w);
    let f = w.cross(momentum).scale(hl);
    // J = I + h (skew(w) I - skew(I w)), by rows
    let rows = [
        V3 {
            x: inertia.x,
            y: hl * (momentum.z - w.z * inertia.y),
            z: hl * (w.y * inertia.z - momentum.y),
        },
        V3 {
            x: hl * (w.z * inertia.x - momentum.z),
            y: inertia.y,
            z: hl * (momentum.x - w.x * inertia.z),
        },
        V3 {
            x: hl * (momentum.y - w.y * inertia.x),
            y: hl * (w.x * inertia.y - momentum.x),
            z: inertia.z,
        },
    ];
    // Cramer: J^-1 = [r1 x r2, r2 x r0, r0 x r1] / det (columns)
    let c = [
        rows[1].cross(rows[2]),
        rows[2].cross(rows[0]),
        rows[0].cross(rows[1]),
    ];
    let determinant = rows[0].dot(c[0]);
    let singular = determinant.abs().lt(L::splat(1e-20));
    let solved = (c[0].scale(f.x) + c[1].scale(f.y) + c[2].scale(f.z))
        .scale(L::splat(1.0) / singular.select(L::splat(1.0), determinant));
    let newton = w - solved;
    let mut done = singular;
    if converged > 0.0 {
        done = done | (hl * hl * w.length_squared()).le(L::splat(converged));
    }
    let mut current = newton;
    let mut result = newton;
    let mut last_change = L::splat(f32::INFINITY);
    for _ in 0..GYROSCOPIC_PASSES {
        let open = not(done);
        if !open.any() {
            break;
        }
        let next = mul(inverse_inertia, exp(current.scale(-hl)).rotate(momentum));
        let change = (next - current).length();
        let contracting = change.lt(last_change);
        // not contracting: keep the Newton step
        result = V3::select(open & not(contracting), newton, result);
        done = done | not(contracting);
        let stepping = open & contracting;
        current = V3::select(stepping, next, current);
        last_change = stepping.select(change, last_change);
        result = V3::select(stepping, next, result);
        if converged > 0.0 {
            done = done | (stepping & change.le(L::splat(converged) * next.length()));
        }
    }
    let w_body = V3::select(singular, w, result);
    let rotated = q.rotate(w_body);
    V3::select(singular, angular, rotated)
}

/// Per-lane product of two vectors component by component (a diagonal matrix times a vector).
#[inline(always)]
fn mul<L: Lane>(a: V3<L>, b: V3<L>) -> V3<L> {
    V3 {
        x: a.x * b.x,
        y: a.y * b.y,
        z: a.z * b.z,
    }
}

/// [`crate::math::quat_from_rotation_vector`] per lane: the exponential map, with its series
/// below 1e-6 rad.
#[inline(always)]
fn exp<L: Lane>(v: V3<L>) -> Q<L> {
    let angle_squared = v.length_squared();
    let angle = angle_squared.sqrt();
    let small = angle.lt(L::splat(1e-6));
    let (sin, cos) = (L::splat(0.5) * angle).sin_cos();
    let series = L::splat(0.5) - angle_squared / L::splat(48.0);
    let factor = small.select(series, sin / angle.max(L::splat(1e-6)));
    let w = small.select(L::splat(1.0) - angle_squared / L::splat(8.0), cos);
    Q {
        x: v.x * factor,
        y: v.y * factor,
        z: v.z * factor,
        w,
    }
}

/// `R diag(d) R^T` per lane, with `R` the rotation of `q`, as the scalar [`Mat3`]s.
#[inline(always)]
fn world_inertia<L: Lane>(q: Q<L>, d: V3<L>) -> [Mat3; MAX_LANES] {
    let one = L::splat(1.0);
    let two = L::splat(2.0);
    let (x2, y2, z2) = (q.x * q.x, q.y * q.y, q.z * q.z);
    let (xy, xz, yz) = (q.x * q.y, q.x * q.z, q.y * q.z);
    let (wx, wy, wz) = (q.w * q.x, q.w * q.y, q.w * q.z);
    // rows of R
    let r0 = V3 {
        x: one - two * (y2 + z2),
        y: two * (xy - wz),
        z: two * (xz + wy),
    };
    let r1 = V3 {
        x: two * (xy + wz),
        y: one - two * (x2 + z2),
        z: two * (yz - wx),
    };
    let r2 = V3 {
        x: two * (xz - wy),
        y: two * (yz + wx),
        z: one - two * (x2 + y2),
    };
    let entry = |a: V3<L>, b: V3<L>| a.x * d.x * b.x + a.y * d.y * b.y + a.z * d.z * b.z;
    let (xx, yy, zz) = (entry(r0, r0), entry(r1, r1), entry(r2, r2));
    let (xy, xz, yz) = (entry(r0, r1), entry(r0, r2), entry(r1, r2));
    std::array::from_fn(|i| {
        if i >= L::W {
            return Mat3::ZERO;
        }
        let (xx, yy, zz) = (xx.at(i), yy.at(i), zz.at(i));
        let (xy, xz, yz) = (xy.at(i), xz.at(i), yz.at(i));
        Mat3::from_cols_array(&[xx, xy, xz, xy, yy, yz, xz, yz, zz])
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::quat_from_rotation_vector;
    use crate::shape::{Axis, Shape};

    /// Sixteen bodies (capsules and boxes, some elongated, some spinning fast enough that the
    /// gyroscopic update runs its fixed-point passes, one over the angular speed limit) with
    /// forces and damping, as the solver's settings give them.
    fn bodies(count: usize) -> Vec<Body> {
        (0..count)
            .map(|i| {
                let x = i as f32;
                let shape = match i % 3 {
                    0 => Shape::Capsule {
                        half_height: 0.1 + 0.05 * x,
                        radius: 0.04,
                        axis: Axis::Y,
                    },
                    1 => Shape::Cuboid {
                        half_extents: Vec3::new(0.3, 0.05 + 0.01 * x, 0.1),
                    },
                    _ => Shape::Sphere { radius: 0.1 },
                };
                let turn = quat_from_rotation_vector(Vec3::new(0.3 * x, -0.2, 0.1 * x));
                let mut body = Body::new("b", BodyKind::Dynamic, shape, 1.0 + 0.5 * x)
                    .with_pose(Vec3::new(x, 1.0, -x), turn);
                body.linear_velocity = Vec3::new(0.1 * x, -1.0, 0.5);
                let spin = if i == 7 { 140.0 } else { 0.02 + 2.0 * x };
                body.angular_velocity = Vec3::new(1.0, 0.3 * x, -0.5).normalize() * spin;
                body.external_force = Vec3::new(0.0, 0.0, 2.0 * x);
                body
            })
            .collect()
    }

    fn settings(substeps: u32) -> Settings {
        Settings {
            substeps,
            angular_speed_limit: 100.0,
            linear_damping: 0.05,
            angular_damping: 0.5,
            ..Settings::default()
        }
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() <= 2e-5 * (1.0 + a.length())
    }

    /// Steps 3.1-3.2 and 3.4 in lanes give each body what the scalar per-body steps give it,
    /// to rounding (the lanes' `sin_cos` and `atan2` against libm's), with one step a frame
    /// (four gyroscopic passes) and with substeps (passes until converged), for a full batch
    /// and a short one; a fixed body in a batch runs the scalar code to the bit, and the
    /// others get what they get in a batch without it.
    #[test]
    fn the_lanes_integrate_and_commit_as_the_scalar_code() {
        type L = crate::lanes::portable::Portable<16>;
        for (count, substeps) in [(16, 1), (16, 4), (5, 4)] {
            let settings = settings(substeps);
            let h = settings.dt / substeps as f32;
            let (mut scalar, mut lanes) = (bodies(count), bodies(count));
            let mut scalar_hot = vec![SolverBody::default(); count];
            let mut lanes_hot = vec![SolverBody::default(); count];
            for (body, hot) in scalar.iter_mut().zip(&mut scalar_hot) {
                integrate_velocity(body, &settings, h);
                *hot = predict_pose(body, h);
            }
            predict_batch::<L>(&mut lanes, &mut lanes_hot, &settings, h);
            for i in 0..count {
                let what = format!("body {i} of {count}, {substeps} substeps");
                let (s, l) = (&scalar[i], &lanes[i]);
                assert!(close(s.linear_velocity, l.linear_velocity), "{what}");
                assert!(close(s.angular_velocity, l.angular_velocity), "{what}");
                assert!(
                    l.angular_velocity.length() <= 100.0 * (1.0 + 1e-6),
                    "{what}"
                );
                let (s, l) = (&scalar_hot[i], &lanes_hot[i]);
                assert!(close(s.position, l.position), "{what}");
                assert!(
                    s.orientation.dot(l.orientation).abs() > 1.0 - 1e-6,
                    "{what}"
                );
                for k in 0..3 {
                    let (a, b) = (s.inverse_inertia.col(k), l.inverse_inertia.col(k));
                    assert!(close(a, b), "{what}: inverse inertia {a} against {b}");
                }
            }
            // the solver's corrections, then the commit
            for (i, hot) in scalar_hot.iter_mut().chain(&mut lanes_hot).enumerate() {
                hot.position += Vec3::new(0.001, -0.002, 0.0005 * (i % count) as f32);
                hot.orientation = crate::math::rotate_by_small(hot.orientation, Vec3::splat(0.01));
            }
            let lanes_before = lanes.clone();
            for (body, hot) in scalar.iter_mut().zip(&scalar_hot) {
                commit_pose(body, hot, h);
            }
            commit_batch::<L>(&mut lanes, &lanes_hot, h);
            for i in 0..count {
                let what = format!("commit, body {i} of {count}");
                let (s, l) = (&scalar[i], &lanes[i]);
                assert!(close(s.linear_velocity, l.linear_velocity), "{what}");
                assert!(close(s.angular_velocity, l.angular_velocity), "{what}");
                assert_eq!(l.position, lanes_hot[i].position, "{what}");
                assert_ne!(l.position, lanes_before[i].position, "{what}");
                for k in 0..3 {
                    let (a, b) = (
                        s.inverse_inertia_world.col(k),
                        l.inverse_inertia_world.col(k),
                    );
                    assert!(close(a, b), "{what}: inverse inertia {a} against {b}");
                }
            }
        }
        // a fixed body in the batch: the scalar code, bit for bit; the others as without it
        let settings = settings(4);
        let h = 1.0 / 240.0;
        let mut with_fixed = bodies(16);
        with_fixed[3] = Body::new("floor", BodyKind::Fixed, Shape::HalfSpace, 1.0);
        let mut fixed = [with_fixed[3].clone()];
        let mut fixed_hot = [SolverBody::default()];
        integrate_velocity(&mut fixed[0], &settings, h);
        fixed_hot[0] = predict_pose(&fixed[0], h);
        let mut others: Vec<Body> = (0..16)
            .filter(|&i| i != 3)
            .map(|i| with_fixed[i].clone())
            .collect();
        let mut others_hot = vec![SolverBody::default(); 15];
        predict_batch::<L>(&mut others, &mut others_hot, &settings, h);
        let mut hot = vec![SolverBody::default(); 16];
        predict_batch::<L>(&mut with_fixed, &mut hot, &settings, h);
        for i in 0..16 {
            let (body, hot_body) = match i {
                3 => (&fixed[0], &fixed_hot[0]),
                _ => (
                    &others[i - (i > 3) as usize],
                    &others_hot[i - (i > 3) as usize],
                ),
            };
            assert_eq!(
                with_fixed[i].angular_velocity, body.angular_velocity,
                "body {i}"
            );
            assert_eq!(hot[i].orientation, hot_body.orientation, "body {i}");
            assert_eq!(hot[i].position, hot_body.position, "body {i}");
        }
    }
}
