//! The rod constraint (paper §5): an inextensible Kirchhoff rod between bodies a and b, shaped as
//! a circular arc, with soft bending and twisting. All parts are solved in one function (§7).
//!
//! Ends at the centres of mass, frames fixed in the bodies (eq. 2):
//! `gamma(0) = p_a`, `gamma(1) = p_b`, `F(0) = q_a F_a`, `F(1) = q_b F_b`; the body tangents
//! `t_i = F(i) x` and normals `F(i) y`. With the offset `o = p_b - p_a`, `o^ = o / |o|` and the
//! bend angle `psi = acos(t_a . t_b)`:
//!
//! - curve (eq. 6), hard: `C_curve = t_a + t_b - 2 (t_a . o^) o^ = 0`, i.e. `t_b = S t_a` with
//!   `S = 2 o^ o^T - E` the half turn about `o^`. We solve its scalar form
//!   `C = angle(t_b, r)`, `r = S t_a`, with `n = (t_b x r) / |t_b x r|`, `m = n x r`:
//!   `dC/dtheta_a = S n`, `dC/dtheta_b = -n`,
//!   `dC/dp_b = -dC/dp_a = g_o = (2 / |o|) (E - o^ o^T) ((t_a . o^) m + (m . o^) t_a)`.
//!   The full gradient (rotations and positions) keeps the pair's momentum: `C` is invariant
//!   under moving and turning the pair together.
//! - length (eq. 9), hard: `C_len = |p_b - p_a| - 2 l_0 sin(psi/2) / psi`, corrected by linear
//!   motion along `o^` only, at fixed `psi`, as the paper does.
//! - bend (eq. 11), soft: `C_bend = alpha_b psi^2 / (2 l_0^2)`; each iteration removes the
//!   fraction `alpha_b` of `psi` by equal and opposite turns about `t_a x t_b`
//!   (`alpha_b = 0`: free bending; `1`: straight).
//! - twist (eq. 12-13), soft: `C_twist = alpha_t tau^2 / 2`; each iteration removes the fraction
//!   `alpha_t` of `tau` by equal and opposite turns about `t_b`. `tau` is measured
//!   ([`TwistMode::Exact`]) as the signed turn about `t_b` left between `F(1)` and `F(0)`
//!   carried along the arc (the bend by `psi` about `t_a x t_b`, the natural frame's parallel
//!   transport), or ([`TwistMode::Paper`]) as eq. 12, `tau = xi - psi` with `xi` the total
//!   angle between `F(0)` and `F(1)`: it has no sign (we take the sign from the exact twist) and
//!   underestimates a twist on a bent rod.
//! - the parts in order ([`BendTwist`]): by default one after the other, each measured on the
//!   frames the previous one left (bend, twist, curve, length); or, sharing the frames (§7), as
//!   two blocks: bend and twist as one 2x2 block over `((t_a x t_b)^, t_b)` that removes both
//!   fractions at once, then curve and length measured on the same frames (with the paper's
//!   offset-only length their block is diagonal).
//!
//! Stiffness in physical units (an alternative to the alphas, not in the paper): the fraction
//! alpha removed per iteration makes the same alpha stiffer at more iterations, substeps or a
//! shorter step. With `bend_stiffness` k (N m/rad) the bend is instead the compliant constraint
//! `C = psi` of energy `k psi^2 / 2`, solved in compliance form (XPBD, Macklin, Mueller and
//! Chentanez 2016, eq. 18): per substep of `h`, with `alpha~ = 1 / (k h^2)` and the multiplier
//! `lambda` reset to 0, each iteration applies
//! `d lambda = (-psi - alpha~ lambda) / (w + alpha~)`
//! as the angular impulse `d lambda (t_a x t_b)^` on b and its negative on a, `w` the pair's
//! inverse inertia about that axis. The twist likewise with `C = tau` about `t_b`
//! (`twist_stiffness`). Once the iterations converge, the rod holds the torque `k psi` whatever
//! their number (`tests/it/rod.rs` measures it). Damping `c` (N m s/rad) acts on the velocities
//! after the substep ([`RodRow::damp_velocities`]).
//!
//! The arc (eq. 7-8, in a form stable at small `psi`): with `k` the unit normal of `t_a` toward
//! `t_b`, `gamma(s) = p_a + l_0 (sin(psi s)/psi t_a + (1 - cos(psi s))/psi k)`, whose chord is
//! eq. 9. Its natural frame at `s` is `F(0)` turned by `psi s` about `t_a x t_b`; the material
//! frame adds the twist `tau s` about the tangent.

use super::Violation;
use crate::body::{Body, BodyId};
use crate::math::{angle_between, any_perpendicular, Quat, Vec3};

mod geometry;
mod row;
mod twist;

pub use geometry::{
    arc_point, chord_ratio, chord_ratio_derivative, curve_error, curve_gradient, curve_projection,
    curve_vector, length_error, offset_axis, CurveGradient,
};
pub use row::{Compliant, RodRow};
pub use twist::{measure_twist, twist_exact, twist_paper};

/// How the length constraint (eq. 9) is corrected.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LengthCorrection {
    /// The paper's: linear motion along o^ at fixed psi. Its force is not along the gradient of
    /// eq. 9, so on a freely bending rod it does work (`tests/it/rod.rs` measures the gain).
    #[default]
    Offset,
    /// Along the full gradient of eq. 9: also turns the bodies through psi,
    /// `dC/dtheta_b = -dC/dtheta_a = -l_0 c'(psi) (t_a x t_b)^`, with `c(psi) = 2 sin(psi/2)/psi`.
    Gradient,
}

/// How the rod's parts are projected each iteration: one after the other, or the soft pair and
/// the hard pair each as one block.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BendTwist {
    /// One after the other, each measured on the frames the previous part left: bend about
    /// `(t_a x t_b)^`, twist about `t_b`, curve, length (the reference).
    #[default]
    Sequential,
    /// Two blocks (§7: "share some calculations common to each"):
    ///
    /// - Bend and twist measured on the same frames and removed together as one 2x2 block over
    ///   the orthonormal pair `(t_a x t_b)^, t_b`: to first order each iteration removes
    ///   exactly `alpha_b` of psi and `alpha_t` of tau, where one row after the other lets each
    ///   turn leak into the other's axis through the inertia. Where only one part acts (an
    ///   alpha of 0, a straight rod, a stiffness in physical units) it is that part's row, as
    ///   in [`Self::Sequential`].
    /// - Curve and length measured on the same frames (the ones the bend and twist left). With
    ///   the paper's [`LengthCorrection::Offset`] their 2x2 block is diagonal: the length moves
    ///   the bodies along `o^` only, and the curve's positional gradient `g_o` is across `o^`
    ///   (its rotations do not enter the length's offset-only row). So the block solve is each
    ///   row from the same frames. What it leaves to the next iteration is the change of psi
    ///   the curve's turn makes, which the sequential length sees at once (`tests/it/rod.rs`:
    ///   at most 1.9 mm of length error after an iteration from a 2-3 cm, 0.3 rad kick, and a
    ///   valid arc in as few iterations). With [`LengthCorrection::Gradient`] the length turns
    ///   the bodies too, and it stays after the curve.
    ///
    /// Two frame products and two turns per body less than [`Self::Sequential`].
    Block,
}

/// How the twist angle tau is measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TwistMode {
    /// Signed turn about the end tangent after parallel transport along the arc.
    #[default]
    Exact,
    /// The paper's eq. 12, `tau = xi - psi` (unsigned; underestimates on bent rods).
    Paper,
}

/// A rod part's stiffness in physical units, solved in compliance form (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Stiffness {
    /// Restoring torque per radian (N m/rad), > 0.
    pub stiffness: f32,
    /// Damping torque per rad/s of bend or twist rate (N m s/rad), >= 0.
    pub damping: f32,
}

/// A rod (§5) between two bodies' centres of mass: hard curve (eq. 6) and length (eq. 9), soft bend
/// (eq. 11) and twist (eq. 12-13).
#[derive(Clone, Debug)]
pub struct Rod {
    /// Name, for failure reports and recordings.
    pub name: String,
    /// Body at the rod's start, s = 0.
    pub body_a: BodyId,
    /// Body at the rod's end, s = 1.
    pub body_b: BodyId,
    /// Rod frame in each body (eq. 2): x is the body tangent, y the body normal.
    pub local_frame_a: Quat,
    /// Rod frame in body b (see `local_frame_a`).
    pub local_frame_b: Quat,
    /// Rest length l_0 (m).
    pub rest_length: f32,
    /// Softness (alphas or stiffness) and methods (twist measure, length correction).
    pub params: RodParams,
}

/// A rod's softness and methods, what scenes choose per rod and per rod spine.
///
/// The defaults are the rod spine's (alpha_b 0.1, alpha_t 0.5); [`Rod::instantiate`] starts a
/// rod with both alphas 0 (no bend or twist correction) until its builder sets them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RodParams {
    /// Bending relaxation alpha_b in [0, 1] (eq. 11); default 0.1.
    pub alpha_bend: f32,
    /// Twisting relaxation alpha_t in [0, 1] (eq. 12-13); default 0.5.
    pub alpha_twist: f32,
    /// Bending stiffness in physical units, replacing `alpha_bend` where set.
    pub bend_stiffness: Option<Stiffness>,
    /// Twisting stiffness, replacing `alpha_twist` where set.
    pub twist_stiffness: Option<Stiffness>,
    /// How the twist tau is measured; default exact.
    pub twist_mode: TwistMode,
    /// How the length constraint (eq. 9) is corrected; default the paper's offset correction.
    pub length_correction: LengthCorrection,
    /// How bend and twist are projected; default one after the other.
    pub bend_twist: BendTwist,
}

impl Default for RodParams {
    fn default() -> Self {
        RodParams {
            alpha_bend: 0.1,
            alpha_twist: 0.5,
            bend_stiffness: None,
            twist_stiffness: None,
            twist_mode: TwistMode::Exact,
            length_correction: LengthCorrection::Offset,
            bend_twist: BendTwist::Sequential,
        }
    }
}

/// Everything measured on a rod at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RodState {
    /// Bend angle psi between the tangents t_a and t_b (rad).
    pub psi: f32,
    /// Twist angle tau (rad), measured by the rod's [`TwistMode`].
    pub tau: f32,
    /// eq. 9 (m).
    pub length_error: f32,
    /// angle between t_b and the reflection of t_a about o^ (rad).
    pub curve_error: f32,
}

impl Rod {
    /// Instantiates a rod at the bodies' current poses (§6): rest length `|p_b - p_a|` and both
    /// tangents along the offset, so the rod starts straight and every constraint holds.
    /// `normal_hint` picks the body normals (projected off the tangent).
    pub fn instantiate(
        name: impl Into<String>,
        bodies: &[Body],
        body_a: BodyId,
        body_b: BodyId,
        normal_hint: Vec3,
    ) -> Result<Rod, String> {
        let name = name.into();
        let (a, b) = (&bodies[body_a.index()], &bodies[body_b.index()]);
        let offset = b.position - a.position;
        let rest_length = offset.length();
        if !(rest_length > 1e-4) {
            return Err(format!("rod \"{name}\": the body centres coincide (rest length {rest_length} m); a rod needs a positive rest length"));
        }
        let tangent = offset / rest_length;
        let normal = (normal_hint - normal_hint.dot(tangent) * tangent)
            .try_normalize()
            .unwrap_or_else(|| any_perpendicular(tangent));
        let frame = Quat::from_mat3(&glam::Mat3::from_cols(
            tangent,
            normal,
            tangent.cross(normal),
        ))
        .normalize();
        Ok(Rod {
            name,
            body_a,
            body_b,
            local_frame_a: (a.orientation.inverse() * frame).normalize(),
            local_frame_b: (b.orientation.inverse() * frame).normalize(),
            rest_length,
            params: RodParams {
                alpha_bend: 0.0,
                alpha_twist: 0.0,
                ..RodParams::default()
            },
        })
    }

    /// World rod frames F(0), F(1) at the preview poses.
    pub fn frames(&self, a: &Body, b: &Body) -> (Quat, Quat) {
        (
            a.orientation * self.local_frame_a,
            b.orientation * self.local_frame_b,
        )
    }

    /// Twist tau (rad) between the world rod frames F(0) and F(1), by the rod's [`TwistMode`].
    pub fn twist(&self, frame_a: Quat, frame_b: Quat) -> f32 {
        measure_twist(self.params.twist_mode, frame_a, frame_b)
    }

    /// The prepare stage: the rod as the solver stores it.
    pub fn prepare(&self) -> RodRow {
        RodRow {
            body_a: self.body_a.0,
            body_b: self.body_b.0,
            frame_a: self.local_frame_a,
            frame_b: self.local_frame_b,
            rest_length: self.rest_length,
            alpha_bend: self.params.alpha_bend,
            alpha_twist: self.params.alpha_twist,
            bend_compliant: self.params.bend_stiffness.map(Compliant::new),
            twist_compliant: self.params.twist_stiffness.map(Compliant::new),
            twist_mode: self.params.twist_mode,
            length_correction: self.params.length_correction,
            bend_twist: self.params.bend_twist,
        }
    }

    /// Bend, twist, length error (eq. 9) and curve error (eq. 6) at the preview poses.
    pub fn state(&self, a: &Body, b: &Body) -> RodState {
        let (fa, fb) = self.frames(a, b);
        let (ta, tb) = (fa * Vec3::X, fb * Vec3::X);
        let (pa, pb) = (a.position, b.position);
        RodState {
            psi: angle_between(ta, tb),
            tau: self.twist(fa, fb),
            length_error: length_error(pa, ta, pb, tb, self.rest_length),
            curve_error: curve_error(pa, ta, pb, tb),
        }
    }

    /// Dislocation |C_len| (m) and the curve error (rad), the rod's hard constraints.
    pub fn violation(&self, a: &Body, b: &Body) -> Violation {
        let s = self.state(a, b);
        Violation {
            dislocation: s.length_error.abs(),
            angular: s.curve_error,
        }
    }

    /// Point gamma(s) and material frame F(s) of the arc at the current poses, s in [0, 1].
    /// The arc is built from p_a and t_a; any residual gap at p_b is shared linearly along s so
    /// the drawn curve always ends at both centres.
    pub fn sample(&self, a: &Body, b: &Body, s: f32) -> (Vec3, Quat) {
        let (fa, fb) = self.frames(a, b);
        let (ta, tb) = (fa * Vec3::X, fb * Vec3::X);
        let end = arc_point(a.position, ta, tb, self.rest_length, 1.0);
        let gap = b.position - end;
        let point = arc_point(a.position, ta, tb, self.rest_length, s) + s * gap;
        let psi = angle_between(ta, tb);
        let bend_axis = ta
            .cross(tb)
            .try_normalize()
            .unwrap_or_else(|| any_perpendicular(ta));
        let natural = crate::math::quat_from_axis_angle(bend_axis, psi * s) * fa;
        let frame = natural * crate::math::quat_from_rotation_x(self.twist(fa, fb) * s);
        (point, frame.normalize())
    }
}
