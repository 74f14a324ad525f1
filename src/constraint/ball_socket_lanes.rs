//! Ball-and-socket joints W at a time (paper §7: "branch-free SIMD code, solving four
//! constraints at once"): the maths of [`JointRow::solve`] with one joint per lane.
//!
//! Per iteration, as the scalar code: spring, limits, point. Every scalar `if` becomes a mask:
//! each part computes its correction on all lanes and applies it through `apply_angular` /
//! `apply_positional`, which leave a lane untouched where the scalar code would have returned
//! early (zero-length error, zero effective mass, a limit not reached, an immovable body). Rows
//! without a spring get relaxation 0 and rows without a limit get infinite bounds, so their
//! lanes produce no correction. Per-batch branches only where all lanes agree: the spring and
//! limit parts are skipped when no lane has one, and the cheap or exact point solve when no
//! lane uses it (a mixed batch computes both and selects).
//!
//! The degenerate cases follow the scalar guards: `|C| < 1e-9` (cheap) / `|C|^2 < 1e-18`
//! (exact), `|det K| < 1e-20`, `w <= 0`, rotation angle `< 1e-9`, and a swing axis that does
//! not normalise (glam's `try_normalize`) falls back to glam's `any_orthonormal_vector`.

use super::limits::HINGE_BLOCK_MAX_SWING;
use super::{JointFlavour, JointRow};
use crate::body::Body;
use crate::lanes::{
    body_indices, exact, not, padded, relative_rotation, relative_rotation_across, BodyLanes, Lane,
    SymM3, MAX_LANES, Q, V3,
};
use crate::math::Quat;
use crate::solver_body::SharedBodies;
use std::f32::consts::{PI, TAU};

/// Solves `L::W` rows sharing no movable body at once: packed, then one projection (the solver
/// packs once a frame and solves the packed batch every iteration).
#[inline(always)]
pub fn solve_lanes<L: Lane>(rows: &mut [JointRow], bodies: SharedBodies) {
    JointLanes::<L>::pack(rows).solve(bodies);
}

/// The spring part of `L::W` rows: relaxation 0 (no correction) where a row has none.
#[derive(Clone, Copy, Debug)]
struct SpringLanes<L> {
    relaxation: L,
    rest: Q<L>,
}

/// The limit part of `L::W` rows: infinite bounds (no correction) where a row has none.
#[derive(Clone, Copy, Debug)]
struct LimitLanes<L> {
    /// Bit `i`: row `i` of the batch has a limit.
    limited: u16,
    swing_max: L,
    twist_min: L,
    twist_max: L,
    start_twist: L,
    frame_a: Q<L>,
    frame_b: Q<L>,
    /// The lanes whose hinge aligns its axes by the 2x2 block (exact flavour, `swing_max = 0`),
    /// when the batch has any.
    hinge_block: Option<L>,
}

/// `L::W` joint rows of one colour in lanes, packed once a frame, with the limits' starting
/// twist taken in lanes at each substep's start ([`JointLanes::begin_substep`]): the rows' constants read straight into registers every iteration instead of
/// gathered field by field from the rows (Box2D v3 keeps its SIMD contact constraints so).
/// Parts no row of the batch has are `None` and skipped.
#[derive(Clone, Copy, Debug)]
pub struct JointLanes<L> {
    /// The batch's own rows (lanes past them repeat the first).
    rows: u8,
    index_a: [u32; MAX_LANES],
    index_b: [u32; MAX_LANES],
    anchor_a: V3<L>,
    anchor_b: V3<L>,
    spring: Option<SpringLanes<L>>,
    limit: Option<LimitLanes<L>>,
    /// Which point solve: all cheap, all exact, or a mask of the exact lanes.
    point: PointFlavours<L>,
}

#[derive(Clone, Copy, Debug)]
enum PointFlavours<L> {
    Cheap,
    Exact,
    Mixed { exact: L },
}

impl<L: Lane> JointLanes<L> {
    /// One to `L::W` rows sharing no movable body (lanes past the last repeat the first:
    /// [`padded`]).
    #[inline(always)]
    pub fn pack(rows: &[JointRow]) -> Self {
        assert!((1..=L::W).contains(&rows.len()), "a batch is one to W rows");
        let row = |i: usize| padded(rows, i);
        let (index_a, index_b) = body_indices::<L, _>(rows, |r| (r.body_a, r.body_b));
        // (lanes are made outside closures, whose bodies would compile outside the function
        // `Lane::dispatch` compiles for the lane type's instructions)
        let spring = match rows.iter().any(|r| r.spring.is_some()) {
            true => Some(SpringLanes {
                relaxation: L::from_fn(|i| row(i).spring.map_or(0.0, |s| s.relaxation)),
                rest: Q::from_fn(|i| row(i).spring.map_or(Quat::IDENTITY, |s| s.rest)),
            }),
            false => None,
        };
        let limit = |i: usize| row(i).limit;
        let limit = match rows.iter().any(|r| r.limit.is_some()) {
            false => None,
            true => Some(LimitLanes {
                limited: (rows.iter().enumerate())
                    .filter(|(_, r)| r.limit.is_some())
                    .fold(0, |bits, (i, _)| bits | 1 << i),
                swing_max: L::from_fn(|i| limit(i).map_or(f32::INFINITY, |l| l.swing_max)),
                twist_min: L::from_fn(|i| limit(i).map_or(f32::NEG_INFINITY, |l| l.twist_min)),
                twist_max: L::from_fn(|i| limit(i).map_or(f32::INFINITY, |l| l.twist_max)),
                start_twist: L::from_fn(|i| {
                    if limit(i).is_some() {
                        row(i).start_twist
                    } else {
                        0.0
                    }
                }),
                frame_a: Q::from_fn(|i| row(i).frame_a),
                frame_b: Q::from_fn(|i| row(i).frame_b),
                hinge_block: match rows.iter().any(hinge_block) {
                    true => Some(L::from_fn(|i| hinge_block(row(i)) as u32 as f32).gt(L::zero())),
                    false => None,
                },
            }),
        };
        let any_cheap = rows.iter().any(|r| r.flavour == JointFlavour::Cheap);
        let any_exact = rows.iter().any(|r| r.flavour == JointFlavour::Exact);
        let point = match (any_cheap, any_exact) {
            (true, false) => PointFlavours::Cheap,
            (false, true) => PointFlavours::Exact,
            _ => PointFlavours::Mixed {
                exact: L::from_fn(|i| {
                    if row(i).flavour == JointFlavour::Exact {
                        1.0
                    } else {
                        0.0
                    }
                })
                .gt(L::zero()),
            },
        };
        JointLanes {
            rows: rows.len() as u8,
            index_a,
            index_b,
            anchor_a: V3::from_fn(|i| row(i).anchor_a),
            anchor_b: V3::from_fn(|i| row(i).anchor_b),
            spring,
            limit,
            point,
        }
    }

    /// The substep's constants from the bodies' poses at its start: the limits' starting twist,
    /// [`JointRow::begin_substep`] lane by lane (the same arithmetic, so the same bits as
    /// packing the rows each substep), so a batch packed once a frame serves all its substeps.
    #[inline(always)]
    pub fn begin_substep(&mut self, bodies: &[Body]) {
        let Some(limit) = &mut self.limit else {
            return;
        };
        // the scalar `AngularLimit::start_twist` in lanes, to the bit (`exact`); padded lanes
        // repeat the first row, rows without a limit keep 0
        let (index_a, index_b) = (&self.index_a, &self.index_b);
        let orientation_a = Q::<L>::from_fn(|i| bodies[index_a[i] as usize].orientation);
        let orientation_b = Q::<L>::from_fn(|i| bodies[index_b[i] as usize].orientation);
        let frame_a = exact::quat_mul(orientation_a, limit.frame_a);
        let frame_b = exact::quat_mul(orientation_b, limit.frame_b);
        let twist = exact::start_twist(frame_a, frame_b);
        let limited = L::from_fn(|i| {
            let row = if i < self.rows as usize { i } else { 0 };
            (limit.limited & (1 << row) != 0) as u32 as f32
        });
        limit.start_twist = limited.gt(L::zero()).select(twist, L::zero());
    }

    /// One projection of every lane's joint: gather, spring, limits, point, scatter.
    #[inline(always)]
    pub fn solve(&self, bodies: SharedBodies) {
        let (index_a, index_b) = (&self.index_a[..L::W], &self.index_b[..L::W]);
        // SAFETY: the rows of a batch share no movable body, and no other thread touches them
        // (the caller's colouring); immovable bodies are only read.
        let (mut a, mut b) = unsafe {
            (
                BodyLanes::<L>::gather(bodies, index_a),
                BodyLanes::<L>::gather(bodies, index_b),
            )
        };
        self.solve_bodies(&mut a, &mut b);
        // SAFETY: as above; scatter skips immovable bodies, which may repeat across lanes.
        unsafe {
            a.scatter(bodies, index_a);
            b.scatter(bodies, index_b);
        }
    }

    /// The kernel on gathered bodies.
    #[inline(always)]
    fn solve_bodies(&self, a: &mut BodyLanes<L>, b: &mut BodyLanes<L>) {
        let movable_a = movable(a);
        let movable_b = movable(b);

        // Spring: remove `relaxation` of the rotation q_a q_rest q_b^-1.
        if let Some(spring) = &self.spring {
            let error = a
                .orientation
                .mul(spring.rest)
                .mul(b.orientation.conjugate())
                .rotation_vector();
            relative_rotation(a, b, movable_a, movable_b, error.scale(spring.relaxation));
        }

        // Limits: swing cone, then twist unwrapped next to the substep's starting twist.
        if let Some(limit) = &self.limit {
            let (frame_a, frame_b) = (limit.frame_a, limit.frame_b);
            let mut fa = a.orientation.mul(frame_a);
            let mut fb = b.orientation.mul(frame_b);
            let (ax, bx) = (fa.x_axis(), fb.x_axis());
            let cross = ax.cross(bx);
            let swing = cross.length().atan2(ax.dot(bx));
            let over = swing.gt(limit.swing_max);
            // Lanes not over the cone would get a zero rotation, which the angle guard skips: a
            // batch with none over (most of the time) skips the part, bit for bit the same.
            if over.any() {
                // glam's try_normalize fails where 1 / |v| is not finite.
                let (axis, _) = cross.normalize_or(ax.any_orthonormal(), 1.0 / f32::MAX);
                let amount = over.select(-(swing - limit.swing_max), L::zero());
                let rotation = axis.scale(amount);
                match limit.hinge_block {
                    None => relative_rotation(a, b, movable_a, movable_b, rotation),
                    Some(block) => {
                        let block = block & swing.lt(L::splat(HINGE_BLOCK_MAX_SWING));
                        let row = not(block);
                        if (over & row).any() {
                            relative_rotation(a, b, movable_a & row, movable_b & row, rotation);
                        }
                        let (block_a, block_b) = (movable_a & block, movable_b & block);
                        relative_rotation_across(a, b, block_a, block_b, rotation, ax);
                    }
                }
                fa = a.orientation.mul(frame_a);
                fb = b.orientation.mul(frame_b);
            }

            let r = fa.conjugate().mul(fb);
            let twist = wrap_angle(L::splat(2.0) * r.x.atan2(r.w));
            let start_twist = limit.start_twist;
            let unwrapped = start_twist + wrap_angle(twist - start_twist);
            let excess = unwrapped.gt(limit.twist_max).select(
                unwrapped - limit.twist_max,
                unwrapped
                    .lt(limit.twist_min)
                    .select(unwrapped - limit.twist_min, L::zero()),
            );
            // A zero excess gives a zero rotation, which the angle guard skips (as above).
            if (excess.lt(L::zero()) | excess.gt(L::zero())).any() {
                relative_rotation(a, b, movable_a, movable_b, fb.x_axis().scale(-excess));
            }
        }

        // Point: the dislocation at the freshest poses, cheap (one row along the error) or
        // exact (the 3x3 block).
        let ra = a.orientation.rotate(self.anchor_a);
        let rb = b.orientation.rotate(self.anchor_b);
        let d = (b.position + rb) - (a.position + ra);
        let point = Dislocation { ra, rb, d };
        let (impulse, active) = match self.point {
            PointFlavours::Cheap => point.along_error(a, b),
            PointFlavours::Exact => point.block(a, b),
            PointFlavours::Mixed { exact } => {
                let (ic, ac) = point.along_error(a, b);
                let (ie, ae) = point.block(a, b);
                (V3::select(exact, ie, ic), exact.select(ae, ac))
            }
        };
        apply_positional(a, impulse, ra, active & movable_a);
        apply_positional(b, -impulse, rb, active & movable_b);
    }
}

/// Whether the row's hinge aligns its axes by the 2x2 block ([`AngularLimit::solve`]'s
/// `hinge_block`: the exact flavour's hinges).
///
/// [`AngularLimit::solve`]: super::limits::AngularLimit::solve
fn hinge_block(row: &JointRow) -> bool {
    row.flavour == JointFlavour::Exact && row.limit.is_some_and(|l| l.swing_max == 0.0)
}

/// Mask of lanes whose body moves (the scalar `inverse_mass == 0` early return).
#[inline(always)]
fn movable<L: Lane>(body: &BodyLanes<L>) -> L {
    body.inverse_mass.gt(L::zero()) | body.inverse_mass.lt(L::zero())
}

/// Wraps an angle in [-2 pi, 2 pi] to [-pi, pi], as [`crate::math::wrap_angle`] does there (every
/// angle wrapped here is twice an `atan2` or the difference of two wrapped angles).
#[inline(always)]
fn wrap_angle<L: Lane>(a: L) -> L {
    let a = a.gt(L::splat(PI)).select(a - L::splat(TAU), a);
    a.lt(L::splat(-PI)).select(a + L::splat(TAU), a)
}

/// [`SolverBody::apply_positional_impulse`](crate::solver_body::SolverBody) on the lanes of
/// `mask`; the other lanes keep their pose exactly.
#[inline(always)]
fn apply_positional<L: Lane>(body: &mut BodyLanes<L>, impulse: V3<L>, r: V3<L>, mask: L) {
    body.position = V3::select(
        mask,
        body.position + impulse.scale(body.inverse_mass),
        body.position,
    );
    let dtheta = body.inverse_inertia.mul_vec(r.cross(impulse));
    body.rotate_preview_where(mask, dtheta);
}

/// A joint's dislocation per lane: the anchors' lever arms `ra`, `rb` and the gap `d` from a's
/// anchor to b's.
#[derive(Clone, Copy)]
struct Dislocation<L> {
    ra: V3<L>,
    rb: V3<L>,
    d: V3<L>,
}

impl<L: Lane> Dislocation<L> {
    /// [`super::parts::point_along_error`] with relaxation 1: the impulse on a (b gets its
    /// negative) and the mask of lanes that apply it.
    ///
    /// The inverse mass along `n = d / |d|` is quadratic in `n`, so `w(d) = |d|^2 w(n)` and the
    /// impulse `n |d| / w(n)` is `d |d|^2 / w(d)`: no square root and one division. It differs from
    /// the scalar code by rounding only; the guards are the same (`|d|^2 < 1e-18` is `|d| < 1e-9`).
    #[inline(always)]
    fn along_error(&self, a: &BodyLanes<L>, b: &BodyLanes<L>) -> (V3<L>, L) {
        let Dislocation { ra, rb, d } = *self;
        let length_squared = d.length_squared();
        let long = not(length_squared.lt(L::splat(1e-18)));
        let angular = |body: &BodyLanes<L>, r: V3<L>| body.angular_inverse_mass(r.cross(d));
        let w =
            (a.inverse_mass + b.inverse_mass) * length_squared + angular(a, ra) + angular(b, rb);
        let positive = w.gt(L::zero());
        let impulse = d.scale(length_squared / positive.select(w, L::splat(1.0)));
        (impulse, long & positive)
    }

    /// [`super::parts::point_block`] with relaxation 1: `P = K^-1 C` by the adjugate of the
    /// symmetric `K = K_a + K_b`, and the mask of lanes that apply it.
    #[inline(always)]
    fn block(&self, a: &BodyLanes<L>, b: &BodyLanes<L>) -> (V3<L>, L) {
        let Dislocation { ra, rb, d } = *self;
        let ka = point_inverse_mass_matrix(a, ra);
        let kb = point_inverse_mass_matrix(b, rb);
        let k = SymM3 {
            xx: ka.xx + kb.xx,
            yy: ka.yy + kb.yy,
            zz: ka.zz + kb.zz,
            xy: ka.xy + kb.xy,
            xz: ka.xz + kb.xz,
            yz: ka.yz + kb.yz,
        };
        // Cofactors of a symmetric matrix (the adjugate is symmetric too).
        let adj = SymM3 {
            xx: k.yy * k.zz - k.yz * k.yz,
            yy: k.xx * k.zz - k.xz * k.xz,
            zz: k.xx * k.yy - k.xy * k.xy,
            xy: k.xz * k.yz - k.xy * k.zz,
            xz: k.xy * k.yz - k.xz * k.yy,
            yz: k.xy * k.xz - k.xx * k.yz,
        };
        let det = k.xx * adj.xx + k.xy * adj.xy + k.xz * adj.xz;
        let moving = not(d.length_squared().lt(L::splat(1e-18)));
        let invertible = not(det.abs().lt(L::splat(1e-20)));
        let active = moving & invertible;
        let inv_det = L::splat(1.0) / invertible.select(det, L::splat(1.0));
        (adj.mul_vec(d).scale(inv_det), active)
    }
}

/// `1/m E - [r] I^-1 [r]` per lane: `-[r] I^-1 [r] = [r]^T I^-1 [r]` has entries
/// `s_i . I^-1 s_j` with the columns `s_j = r x e_j` of `[r]`.
#[inline(always)]
fn point_inverse_mass_matrix<L: Lane>(body: &BodyLanes<L>, r: V3<L>) -> SymM3<L> {
    let zero = L::zero();
    let s0 = V3 {
        x: zero,
        y: r.z,
        z: -r.y,
    };
    let s1 = V3 {
        x: -r.z,
        y: zero,
        z: r.x,
    };
    let s2 = V3 {
        x: r.y,
        y: -r.x,
        z: zero,
    };
    let i = &body.inverse_inertia;
    let (t0, t1, t2) = (i.mul_vec(s0), i.mul_vec(s1), i.mul_vec(s2));
    let m = body.inverse_mass;
    SymM3 {
        xx: m + s0.dot(t0),
        yy: m + s1.dot(t1),
        zz: m + s2.dot(t2),
        xy: s0.dot(t1),
        xz: s0.dot(t2),
        yz: s1.dot(t2),
    }
}
