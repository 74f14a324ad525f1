//! [`RodRow`]s W at a time (paper §7: the rod "as branch-free SIMD code, solving four
//! constraints at once").
//!
//! [`solve_lanes`] is [`RodRow::solve`] with one rod per lane, for the default modes
//! ([`TwistMode::Exact`], [`LengthCorrection::Offset`]): soft bend (eq. 11), soft twist (eq.
//! 12-13, the exact parallel-transport twist), hard curve (eq. 6, full gradient) and hard length
//! (eq. 9, along the offset), in one function and in the scalar order, each part reading the
//! frames the previous part left; or, on the lanes whose rod asks for [`BendTwist::Block`], bend
//! and twist from the same frames as one 2x2 block (where both act), and curve and length from
//! the same frames (a batch with no such rod runs only the sequential code; a batch of block
//! rods only the shared length). Every branch of the scalar code is a mask:
//!
//! - bend only where `alpha_b > 0` and `psi > 1e-7`; its axis `(t_a x t_b)^`, else
//!   `any_perpendicular(t_a)`;
//! - twist only where `alpha_t > 0`; `Quat::from_rotation_arc` with glam's two singular cases
//!   (identity for `t_a . t_b > 1 - 2 eps`, a half turn about `any_perpendicular(t_a)` below
//!   `-(1 - 2 eps)`); `twist_angle` wrapped to [-pi, pi];
//! - `relative_rotation` only where the turn is at least 1e-9 rad and `w > 0`;
//! - curve: `o^` falls back to `t_a` where `|o| <= 1e-12`, `n` to `any_perpendicular(t_b)` where
//!   `sin <= 1e-12`, `g_o = 0` where `|o| <= 1e-6`; corrected only where `C > 1e-7` and `w > 0`;
//! - length: `chord_ratio`'s series where `|psi| < 1e-2`; `o^` falls back to `t_a` (on the
//!   block lanes, whose length shares the curve's `o^`, where `|o| <= 1e-12`); corrected only
//!   where `|C| > 1e-9` and `w > 0`;
//! - a body of zero inverse mass is not turned (as [`SolverBody::apply_angular_impulse`]), and
//!   is never written back.
//!
//! A lane whose guard fails keeps its pose bit for bit, like the scalar code's early return.
//! The lanes differ from the scalar code only by rounding (and `wide`'s polynomial `atan2`,
//! `sin`, `cos`): `tests/it/lanes_rod.rs` measures the agreement.
//!
//! The SIMD solver packs a batch into [`RodLanes`] only when every row uses the default modes
//! ([`is_default_modes`]); a batch with any other mode ([`TwistMode::Paper`],
//! [`LengthCorrection::Gradient`], a stiffness in physical units) is solved with the scalar [`RodRow::solve`] row by row
//! ([`crate::solver::packed`]), so results stay those of the scalar reference up to rounding
//! whatever the modes.
//!
//! [`SolverBody::apply_angular_impulse`]: crate::solver_body::SolverBody::apply_angular_impulse

use super::rod::{BendTwist, LengthCorrection, RodRow, TwistMode};
use crate::lanes::{
    body_indices, not, padded, relative_rotation, relative_rotation_block, BodyLanes, Lane,
    MAX_LANES, Q, V3,
};
use crate::solver_body::SharedBodies;

/// Whether the lane kernel covers this row: the default modes and the paper's alphas (a rod
/// with a stiffness in physical units is solved by the scalar kernel).
#[inline(always)]
pub fn is_default_modes(row: &RodRow) -> bool {
    row.twist_mode == TwistMode::Exact
        && row.length_correction == LengthCorrection::Offset
        && row.bend_compliant.is_none()
        && row.twist_compliant.is_none()
}

/// The scalar [`RodRow::solve`] one row after another.
pub fn solve_scalar(rows: &mut [RodRow], bodies: SharedBodies) {
    for row in rows {
        // SAFETY: the batch's rows share no movable body.
        unsafe {
            bodies.with_pair(
                row.body_a,
                row.body_b,
                #[inline(always)]
                |a, b| row.solve(a, b),
            )
        };
    }
}

/// Exactly `L::W` rows, all in the default modes, sharing no movable body: packed, then
/// solved once (the solver packs once a substep and solves the packed batch every iteration).
#[inline(always)]
pub fn solve_lanes<L: Lane>(rows: &mut [RodRow], bodies: SharedBodies) {
    RodLanes::<L>::pack(rows).solve(bodies);
}

/// `L::W` rods of one colour in lanes, packed once a substep: the rows' constants, one rod per
/// lane, and their bodies.
#[derive(Clone, Copy, Debug)]
pub struct RodLanes<L> {
    index_a: [u32; MAX_LANES],
    index_b: [u32; MAX_LANES],
    /// Rod frame in body a (eq. 2), per lane.
    pub frame_a: Q<L>,
    /// Rod frame in body b (eq. 2), per lane.
    pub frame_b: Q<L>,
    /// Rest length l_0 (m), per lane.
    pub rest_length: L,
    /// Bending relaxation alpha_b (eq. 11), per lane.
    pub alpha_bend: L,
    /// Twisting relaxation alpha_t (eq. 12-13), per lane.
    pub alpha_twist: L,
    /// The lanes whose rod projects bend and twist as one block ([`BendTwist::Block`]), when
    /// the batch has any.
    pub block: Option<L>,
}

impl<L: Lane> RodLanes<L> {
    /// One to `L::W` rows, all in the default modes ([`is_default_modes`]), sharing no movable
    /// body (lanes past the last repeat the first: [`padded`]).
    #[inline(always)]
    pub fn pack(rows: &[RodRow]) -> Self {
        assert!((1..=L::W).contains(&rows.len()), "a batch is one to W rows");
        let row = |i: usize| padded(rows, i);
        debug_assert!(rows.iter().all(is_default_modes));
        let (index_a, index_b) = body_indices::<L, _>(rows, |r| (r.body_a, r.body_b));
        RodLanes {
            index_a,
            index_b,
            frame_a: Q::from_fn(|i| row(i).frame_a),
            frame_b: Q::from_fn(|i| row(i).frame_b),
            rest_length: L::from_fn(|i| row(i).rest_length),
            alpha_bend: L::from_fn(|i| row(i).alpha_bend),
            alpha_twist: L::from_fn(|i| row(i).alpha_twist),
            // (no closure around lane code: see `solve_rod_lanes`)
            block: match rows.iter().any(|r| r.bend_twist == BendTwist::Block) {
                true => {
                    let block = |i: usize| (row(i).bend_twist == BendTwist::Block) as u32 as f32;
                    Some(L::from_fn(block).gt(L::zero()))
                }
                false => None,
            },
        }
    }

    /// One projection of every lane's rod: gathered, [`solve_rod_lanes`], scattered back.
    #[inline(always)]
    pub fn solve(&self, bodies: SharedBodies) {
        let (index_a, index_b) = (&self.index_a[..L::W], &self.index_b[..L::W]);
        // SAFETY: the rows of a batch share no movable body, and no other thread touches them
        // (the caller's colouring); immovable bodies are only read.
        unsafe {
            let mut a = BodyLanes::<L>::gather(bodies, index_a);
            let mut b = BodyLanes::<L>::gather(bodies, index_b);
            solve_rod_lanes(self, &mut a, &mut b);
            a.scatter(bodies, index_a);
            b.scatter(bodies, index_b);
        }
    }
}

/// [`RodRow::solve`] per lane (default modes): bend, twist, curve, length.
#[inline(always)]
pub fn solve_rod_lanes<L: Lane>(row: &RodLanes<L>, a: &mut BodyLanes<L>, b: &mut BodyLanes<L>) {
    let zero = L::zero();
    let movable_a = a.inverse_mass.gt(zero);
    let movable_b = b.inverse_mass.gt(zero);

    // Bend and twist: as one block on the lanes whose rod asks for it and where both act, one
    // after the other on the rest (every lane of a batch without block rods). No closures
    // around lane code here: a closure's body would compile outside the function
    // `Lane::dispatch` compiles for the lane type's instructions.
    let sequential = match row.block {
        Some(block) => Some(bend_and_twist_as_block(row, a, b, block)),
        None => None,
    };
    match sequential {
        None => bend_then_twist(row, a, b, movable_a, movable_b),
        Some(lanes) if lanes.any() => {
            bend_then_twist(row, a, b, movable_a & lanes, movable_b & lanes)
        }
        Some(_) => {}
    }

    // Hard curve (eq. 6), full gradient; the block lanes' length on the same frames
    let (ta, tb) = tangents(row, a, b);
    let curve = curve_projection(a.position, ta, b.position, tb);
    let shared = match row.block {
        Some(block) => Some((
            block,
            length_part(row, (curve.axis, curve.distance), ta, tb),
        )),
        None => None,
    };
    // I^-1 theta once per body, for the effective mass and the turn
    let turn_a = a.inverse_inertia.mul_vec(curve.theta_a);
    let turn_b = b.inverse_inertia.mul_vec(curve.theta_b);
    let w = (a.inverse_mass + b.inverse_mass) * curve.g_o.length_squared()
        + curve.theta_a.dot(turn_a)
        + curve.theta_b.dot(turn_b);
    let active = curve.error.gt(L::splat(1e-7)) & w.gt(zero);
    let lambda = active.select(-curve.error / w.max(L::splat(f32::MIN_POSITIVE)), zero);
    // p_a = -g_o, p_b = g_o
    move_by(a, active, curve.g_o.scale(-lambda));
    move_by(b, active, curve.g_o.scale(lambda));
    a.rotate_preview_where(movable_a & active, turn_a.scale(lambda));
    b.rotate_preview_where(movable_b & active, turn_b.scale(lambda));

    // Hard length (eq. 9), linear motion along o^ at fixed psi: measured on the frames the
    // curve left, or on the block lanes on the curve's
    let LengthLanes { error, axis } = match shared {
        Some((block, shared)) if !not(block).any() => shared,
        Some((block, shared)) => {
            let left = length_on_frames_left(row, a, b);
            LengthLanes {
                error: block.select(shared.error, left.error),
                axis: V3::select(block, shared.axis, left.axis),
            }
        }
        None => length_on_frames_left(row, a, b),
    };
    let w = a.inverse_mass + b.inverse_mass;
    let active = error.abs().gt(L::splat(1e-9)) & w.gt(zero);
    let lambda = active.select(error / w.max(L::splat(f32::MIN_POSITIVE)), zero);
    move_by(a, active, axis.scale(lambda));
    move_by(b, active, axis.scale(-lambda));
}

/// The length error (eq. 9) and the direction o^ it is removed along.
#[derive(Clone, Copy, Debug)]
struct LengthLanes<L> {
    error: L,
    axis: V3<L>,
}

/// [`LengthLanes`] on the bodies' current frames and positions.
#[inline(always)]
fn length_on_frames_left<L: Lane>(
    row: &RodLanes<L>,
    a: &BodyLanes<L>,
    b: &BodyLanes<L>,
) -> LengthLanes<L> {
    let (ta, tb) = tangents(row, a, b);
    let offset = (b.position - a.position).normalize_or(ta, TRY_NORMALIZE_EPS);
    length_part(row, offset, ta, tb)
}

/// [`LengthLanes`] given the offset's direction and length and the tangents.
#[inline(always)]
fn length_part<L: Lane>(
    row: &RodLanes<L>,
    (axis, distance): (V3<L>, L),
    ta: V3<L>,
    tb: V3<L>,
) -> LengthLanes<L> {
    let psi = ta.cross(tb).length().atan2(ta.dot(tb));
    LengthLanes {
        error: distance - row.rest_length * chord_ratio(psi, ta, tb),
        axis,
    }
}

/// Soft bend (eq. 11), then soft twist (eq. 12-13) on the frames the bend left
/// ([`BendTwist::Sequential`]), on the lanes of `seq_a` / `seq_b` (the movable bodies of the
/// lanes that take this path).
#[inline(always)]
fn bend_then_twist<L: Lane>(
    row: &RodLanes<L>,
    a: &mut BodyLanes<L>,
    b: &mut BodyLanes<L>,
    seq_a: L,
    seq_b: L,
) {
    let zero = L::zero();
    // Soft bend (eq. 11): remove alpha_b of psi about t_a x t_b.
    let (ta, tb) = tangents(row, a, b);
    let (axis, psi) = bend_axis_and_angle(ta, ta.cross(tb), ta.dot(tb));
    let bend = row.alpha_bend.gt(zero) & psi.gt(L::splat(1e-7));
    let bend_rotation = axis.scale(-row.alpha_bend * psi);
    relative_rotation(a, b, seq_a & bend, seq_b & bend, bend_rotation);

    // Soft twist (eq. 12-13): remove alpha_t of tau about t_b.
    let (fa, fb) = (
        a.orientation.mul(row.frame_a),
        b.orientation.mul(row.frame_b),
    );
    let (ta, tb) = (fa.x_axis(), fb.x_axis());
    let tau = twist_exact(fa, fb, ta, tb);
    let twist = row.alpha_twist.gt(zero);
    let twist_rotation = tb.scale(-row.alpha_twist * tau);
    relative_rotation(a, b, seq_a & twist, seq_b & twist, twist_rotation);
}

/// [`BendTwist::Block`] on the lanes of `block` where both parts act (alphas above 0, psi
/// above 1e-7): bend and twist from the same frames as one 2x2 block over `(t_a x t_b)^, t_b`.
/// Returns the mask of the other lanes, which take [`bend_then_twist`].
#[inline(always)]
fn bend_and_twist_as_block<L: Lane>(
    row: &RodLanes<L>,
    a: &mut BodyLanes<L>,
    b: &mut BodyLanes<L>,
    block: L,
) -> L {
    let zero = L::zero();
    let (fa, fb) = (
        a.orientation.mul(row.frame_a),
        b.orientation.mul(row.frame_b),
    );
    let (ta, tb) = (fa.x_axis(), fb.x_axis());
    // the bend's cross and dot products are the twist transport's too
    let (cross, dot) = (ta.cross(tb), ta.dot(tb));
    let (axis, psi) = bend_axis_and_angle(ta, cross, dot);
    let both = block & row.alpha_bend.gt(zero) & row.alpha_twist.gt(zero) & psi.gt(L::splat(1e-7));
    if both.any() {
        let tau = twist_along(fa, fb, rotation_arc_given(ta, dot, cross));
        let errors = (-row.alpha_bend * psi, -row.alpha_twist * tau);
        let masks = (movable(a) & both, movable(b) & both);
        relative_rotation_block(a, b, masks, (axis, tb), errors);
    }
    not(both)
}

/// Lanes whose body moves (a body of zero inverse mass is not turned).
#[inline(always)]
fn movable<L: Lane>(body: &BodyLanes<L>) -> L {
    body.inverse_mass.gt(L::zero())
}

/// The bend axis `(t_a x t_b)^` (else `any_perpendicular(t_a)`) and angle psi, from the
/// tangents' cross and dot products.
#[inline(always)]
fn bend_axis_and_angle<L: Lane>(ta: V3<L>, cross: V3<L>, dot: L) -> (V3<L>, L) {
    let (axis, sin) = cross.normalize_or(ta.any_orthonormal(), TRY_NORMALIZE_EPS);
    (axis, sin.atan2(dot))
}

/// Lengths at or below this fail glam's `try_normalize` (its reciprocal is not finite).
const TRY_NORMALIZE_EPS: f32 = 1.0 / f32::MAX;

/// The body tangents `t_a = q_a F_a x`, `t_b = q_b F_b x` (the frame products' first axes: a
/// shorter chain of dependent operations than rotating `F_a x`, measured faster).
#[inline(always)]
fn tangents<L: Lane>(row: &RodLanes<L>, a: &BodyLanes<L>, b: &BodyLanes<L>) -> (V3<L>, V3<L>) {
    (
        a.orientation.mul(row.frame_a).x_axis(),
        b.orientation.mul(row.frame_b).x_axis(),
    )
}

/// `apply_linear_impulse` where `mask` is set, as a displacement `impulse` (before the inverse
/// mass); other lanes keep their position bit for bit.
#[inline(always)]
fn move_by<L: Lane>(body: &mut BodyLanes<L>, mask: L, impulse: V3<L>) {
    let moved = body.position + impulse.scale(body.inverse_mass);
    body.position = V3::select(mask, moved, body.position);
}

/// [`super::rod::chord_ratio`] of the angle `psi` between the unit tangents `ta`, `tb`:
/// `2 sin(psi/2) / psi`, its series where `|psi| < 1e-2`. The sine is read off the tangents,
/// `|t_a - t_b| = 2 sin(psi/2)` (the chord of the unit circle), instead of a polynomial sine.
#[inline(always)]
pub fn chord_ratio<L: Lane>(psi: L, ta: V3<L>, tb: V3<L>) -> L {
    let small = psi.abs().lt(L::splat(1e-2));
    let p2 = psi * psi;
    let series = L::splat(1.0) - p2 / L::splat(24.0) + p2 * p2 / L::splat(1920.0);
    let safe = small.select(L::splat(1.0), psi);
    small.select(series, (ta - tb).length() / safe)
}

/// [`super::rod::twist_exact`] given the frames and their tangents: the signed turn about x
/// between `F(1)` and `F(0)` carried by `Quat::from_rotation_arc(t_a, t_b)`.
#[inline(always)]
pub fn twist_exact<L: Lane>(fa: Q<L>, fb: Q<L>, ta: V3<L>, tb: V3<L>) -> L {
    twist_along(fa, fb, rotation_arc(ta, tb))
}

/// The signed turn about x between `F(1)` and `F(0)` carried by `transport`.
#[inline(always)]
fn twist_along<L: Lane>(fa: Q<L>, fb: Q<L>, transport: Q<L>) -> L {
    let q = transport.mul(fa).conjugate().mul(fb);
    wrap_angle(L::splat(2.0) * q.x.atan2(q.w))
}

/// glam's `Quat::from_rotation_arc` for unit `from`, `to`, its singular cases as selects.
#[inline(always)]
pub fn rotation_arc<L: Lane>(from: V3<L>, to: V3<L>) -> Q<L> {
    rotation_arc_given(from, from.dot(to), from.cross(to))
}

/// [`rotation_arc`] from `from` and the given `from . to` and `from x to`.
#[inline(always)]
fn rotation_arc_given<L: Lane>(from: V3<L>, dot: L, c: V3<L>) -> Q<L> {
    const ONE_MINUS_EPS: f32 = 1.0 - 2.0 * f32::EPSILON;
    let w = L::splat(1.0) + dot;
    let norm = (c.length_squared() + w * w)
        .sqrt()
        .max(L::splat(f32::MIN_POSITIVE));
    let inv = L::splat(1.0) / norm;
    let general = Q {
        x: c.x * inv,
        y: c.y * inv,
        z: c.z * inv,
        w: w * inv,
    };
    let identity = Q {
        x: L::zero(),
        y: L::zero(),
        z: L::zero(),
        w: L::splat(1.0),
    };
    let opposite = dot.lt(L::splat(-ONE_MINUS_EPS));
    let same = dot.gt(L::splat(ONE_MINUS_EPS));
    // a rod folded back on itself is rare: its half turn only when a lane has one
    let general = match opposite.any() {
        true => {
            // from_axis_angle(any_orthonormal(from), pi): sin(pi/2) = 1, cos(pi/2) in f32
            let perpendicular = from.any_orthonormal();
            let half_turn = Q {
                x: perpendicular.x,
                y: perpendicular.y,
                z: perpendicular.z,
                w: L::splat(crate::math::cos(0.5 * std::f32::consts::PI)),
            };
            Q::select(opposite, half_turn, general)
        }
        false => general,
    };
    Q::select(same, identity, general)
}

/// [`crate::math::wrap_angle`] for angles in [-2 pi, 2 pi] (what `2 atan2` gives).
#[inline(always)]
fn wrap_angle<L: Lane>(a: L) -> L {
    use std::f32::consts::{PI, TAU};
    let a = a.gt(L::splat(PI)).select(a - L::splat(TAU), a);
    a.lt(L::splat(-PI)).select(a + L::splat(TAU), a)
}

/// [`super::rod::curve_projection`] per lane: the error and the parts of its gradient
/// (`p_a = -g_o`, `p_b = g_o`, `theta_a = S n`, `theta_b = -n`).
#[derive(Clone, Copy, Debug)]
pub struct CurveLanes<L> {
    /// The curve error (rad): angle between t_b and t_a reflected about o^ (eq. 6).
    pub error: L,
    /// `g_o`, the error's gradient with respect to p_b (rad/m); `-g_o` for p_a.
    pub g_o: V3<L>,
    /// Gradient with respect to body a's rotation vector, `S n`.
    pub theta_a: V3<L>,
    /// Gradient with respect to body b's rotation vector, `-n`.
    pub theta_b: V3<L>,
    /// The offset's direction o^ (`t_a` where `|o| <= 1e-12`).
    pub axis: V3<L>,
    /// The offset's length |o| (m).
    pub distance: L,
}

/// [`super::rod::curve_projection`] per lane: the curve error (eq. 6) and its gradient, from
/// both bodies' centres and world tangents.
#[inline(always)]
pub fn curve_projection<L: Lane>(pa: V3<L>, ta: V3<L>, pb: V3<L>, tb: V3<L>) -> CurveLanes<L> {
    let (o, distance) = (pb - pa).normalize_or(ta, 1e-12);
    let two = L::splat(2.0);
    #[inline(always)]
    fn reflect<L: Lane>(v: V3<L>, o: V3<L>) -> V3<L> {
        o.scale(L::splat(2.0) * v.dot(o)) - v
    }
    let r = reflect(ta, o);
    let (n, sin) = tb.cross(r).normalize_or(tb.any_orthonormal(), 1e-12);
    let error = sin.atan2(tb.dot(r));
    let m = n.cross(r);
    let v = m.scale(ta.dot(o)) + ta.scale(m.dot(o));
    // 2 / |o| (where |o| > 1e-6, so 1e-6 is the floor that keeps the unused lanes finite)
    let g = (v - o.scale(v.dot(o))).scale(two / distance.max(L::splat(1e-6)));
    let g_o = V3::select(distance.gt(L::splat(1e-6)), g, V3::zero());
    CurveLanes {
        error,
        g_o,
        theta_a: reflect(n, o),
        theta_b: -n,
        axis: o,
        distance,
    }
}
