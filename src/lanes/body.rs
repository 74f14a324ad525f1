//! [`BodyLanes`]: W solver bodies gathered into lanes by index and scattered back after the
//! batch, with the body methods of [`crate::solver_body::SolverBody`] per lane.

use super::{not, Lane, SymM3, MAX_LANES, Q, V3};
use crate::solver_body::SharedBodies;

/// W solver bodies, one per lane, gathered by index.
#[derive(Clone, Copy, Debug)]
pub struct BodyLanes<L> {
    /// Preview position p* (m).
    pub position: V3<L>,
    /// Preview orientation q*.
    pub orientation: Q<L>,
    /// Orientation predicted at the substep's start, before any correction.
    pub predicted: Q<L>,
    /// Sum of the rotation vectors applied this substep (rad); `orientation` is `predicted` turned
    /// by it.
    pub rotation_correction: V3<L>,
    /// Inverse mass (1/kg); zero for immovable bodies.
    pub inverse_mass: L,
    /// World inverse inertia (1/(kg m^2)).
    pub inverse_inertia: SymM3<L>,
}

impl<L: Lane> BodyLanes<L> {
    /// Gathers body `index[i]` into lane i.
    ///
    /// # Safety
    /// No other thread may be writing those bodies (see [`SharedBodies`]).
    #[inline(always)]
    pub unsafe fn gather(bodies: SharedBodies, index: &[u32]) -> Self {
        // straight from the bodies' memory: no copies, one load per group of four floats
        // only the first W entries are read: the rest repeat body 0 without another lookup
        let first = bodies.quads(index[0]);
        let quads: [&[[f32; 4]; 6]; MAX_LANES] = std::array::from_fn(|i| {
            if i < L::W {
                bodies.quads(index[i])
            } else {
                first
            }
        });
        // group k of every body, transposed: four fields in lanes
        let group = |k: usize| L::transpose4(std::array::from_fn(|i| &quads[i][k]));
        let [qx, qy, qz, qw] = group(0);
        let [px, py, pz, pw] = group(1);
        let [x, y, z, inverse_mass] = group(2);
        let [cx, cy, cz, xx] = group(3);
        // column-major Mat3 of a symmetric matrix: (x_axis.y, x_axis.z, y_axis.x, y_axis.y)
        let [xy, xz, _, yy] = group(4);
        // (y_axis.z, z_axis.x, z_axis.y, z_axis.z)
        let [yz, _, _, zz] = group(5);
        BodyLanes {
            position: V3 { x, y, z },
            orientation: Q {
                x: qx,
                y: qy,
                z: qz,
                w: qw,
            },
            predicted: Q {
                x: px,
                y: py,
                z: pz,
                w: pw,
            },
            rotation_correction: V3 {
                x: cx,
                y: cy,
                z: cz,
            },
            inverse_mass,
            inverse_inertia: SymM3 {
                xx,
                yy,
                zz,
                xy,
                xz,
                yz,
            },
        }
    }

    /// Writes the moving parts (pose and correction) back to body `index[i]`, skipping
    /// immovable bodies: static bodies may repeat an index across lanes, and never change.
    ///
    /// # Safety
    /// The movable bodies among `index` must be this batch's alone (see [`SharedBodies`]).
    #[inline(always)]
    pub unsafe fn scatter(&self, bodies: SharedBodies, index: &[u32]) {
        let o = self.orientation;
        let orientation = L::untranspose4([o.x, o.y, o.z, o.w]);
        let p = self.position;
        let position = L::untranspose4([p.x, p.y, p.z, self.inverse_mass]);
        let c = self.rotation_correction;
        let correction = L::untranspose4([c.x, c.y, c.z, self.inverse_inertia.xx]);
        for (i, &k) in index.iter().enumerate().take(L::W) {
            // the gathered inverse mass, not a reload: immovable lanes are skipped
            if self.inverse_mass.at(i) == 0.0 {
                continue;
            }
            let quads = bodies.get_mut(k).as_quads_mut();
            quads[0] = orientation[i];
            // the 4th floats are the body's own inverse mass and inertia entry, unchanged
            quads[2] = position[i];
            quads[3] = correction[i];
        }
    }

    /// The turn per unit positional impulse along `n` at offset `r`, `I^-1 (r x n)`, and the
    /// inverse effective mass `1/m + (r x n) . I^-1 (r x n)`: computed once, a point's effective
    /// mass and its turn share it ([`BodyLanes::push_along_where`]).
    #[inline(always)]
    pub fn response(&self, r: V3<L>, n: V3<L>) -> (V3<L>, L) {
        let rn = r.cross(n);
        let turn = self.inverse_inertia.mul_vec(rn);
        (turn, self.inverse_mass + rn.dot(turn))
    }

    /// A positional impulse `amount n` at the offset whose [`BodyLanes::response`] along `n` is
    /// `turn`, on the lanes of `mask`; the other lanes keep their pose and correction bit for
    /// bit (the scalar code applies nothing for them: a zero push would still renormalise the
    /// orientation, and so depend on the other rows of its batch).
    #[inline(always)]
    pub fn push_along_where(&mut self, mask: L, n: V3<L>, turn: V3<L>, amount: L) {
        let moved = self.position + n.scale(amount * self.inverse_mass);
        self.position = V3::select(mask, moved, self.position);
        self.rotate_preview_where(mask, turn.scale(amount));
    }

    /// `SolverBody::apply_positional_impulse` on the lanes of `mask` (the others untouched, as
    /// in [`BodyLanes::push_along_where`]).
    #[inline(always)]
    pub fn apply_positional_impulse_where(&mut self, mask: L, impulse: V3<L>, r: V3<L>) {
        let moved = self.position + impulse.scale(self.inverse_mass);
        self.position = V3::select(mask, moved, self.position);
        let dtheta = self.inverse_inertia.mul_vec(r.cross(impulse));
        self.rotate_preview_where(mask, dtheta);
    }

    /// Turns the preview by the rotation vector `dtheta` on the lanes of `mask`.
    #[inline(always)]
    pub fn rotate_preview_where(&mut self, mask: L, dtheta: V3<L>) {
        let correction = self.rotation_correction + dtheta;
        let orientation = self.predicted.rotate_by_small(correction);
        self.rotation_correction = V3::select(mask, correction, self.rotation_correction);
        self.orientation = Q::select(mask, orientation, self.orientation);
    }

    /// `SolverBody::angular_inverse_mass` per lane: `g . I^-1 g`.
    #[inline(always)]
    pub fn angular_inverse_mass(&self, g: V3<L>) -> L {
        g.dot(self.inverse_inertia.mul_vec(g))
    }
}

/// The constraint parts' `relative_rotation` per lane: turns b by `rotation_b` relative to a,
/// shared by their inertia about the axis; a on the lanes of `mask_a`, b on those of `mask_b`.
///
/// With n = v / |v| the impulse n |v| / w(n) is v |v|^2 / w(v) (w is quadratic): no square
/// root, one division. `|v|^2 < 1e-18` is the scalar `|v| < 1e-9`, and lanes with `w = 0`
/// (both bodies immovable about the axis) are left alone, as the scalar guards do.
#[inline(always)]
pub fn relative_rotation<L: Lane>(
    a: &mut BodyLanes<L>,
    b: &mut BodyLanes<L>,
    mask_a: L,
    mask_b: L,
    rotation_b: V3<L>,
) {
    let angle_squared = rotation_b.length_squared();
    let big = not(angle_squared.lt(L::splat(1e-18)));
    // I^-1 v once per body, for the effective mass and the turn: the turn is (I^-1 v) s
    let (turn_a, turn_b) = (
        a.inverse_inertia.mul_vec(rotation_b),
        b.inverse_inertia.mul_vec(rotation_b),
    );
    let w = rotation_b.dot(turn_a) + rotation_b.dot(turn_b);
    let positive = w.gt(L::zero());
    let active = big & positive;
    let s = angle_squared / positive.select(w, L::splat(1.0));
    a.rotate_preview_where(active & mask_a, -turn_a.scale(s));
    b.rotate_preview_where(active & mask_b, turn_b.scale(s));
}

/// [`crate::constraint::parts::relative_rotation_across`] per lane: turns b by `rotation_b`
/// (across the unit `axis`) relative to a by the 2x2 block across `axis`; a on the lanes of
/// `mask_a`, b on those of `mask_b`.
#[inline(always)]
pub fn relative_rotation_across<L: Lane>(
    a: &mut BodyLanes<L>,
    b: &mut BodyLanes<L>,
    mask_a: L,
    mask_b: L,
    rotation_b: V3<L>,
    axis: V3<L>,
) {
    let u = axis.any_orthonormal();
    let v = axis.cross(u);
    let errors = (rotation_b.dot(u), rotation_b.dot(v));
    relative_rotation_block(a, b, (mask_a, mask_b), (u, v), errors);
}

/// [`crate::constraint::parts::relative_rotation_block`] per lane: turns b relative to a by
/// `e_u` about `u` and `e_v` about `v` at once; a on the lanes of `mask_a`, b on those of
/// `mask_b`. Lanes with no error or a singular block are left alone. The turn per body is
/// `I^-1 L` from the products `I^-1 u`, `I^-1 v` the block is built of.
#[inline(always)]
pub fn relative_rotation_block<L: Lane>(
    a: &mut BodyLanes<L>,
    b: &mut BodyLanes<L>,
    (mask_a, mask_b): (L, L),
    (u, v): (V3<L>, V3<L>),
    (eu, ev): (L, L),
) {
    let big = not((eu * eu + ev * ev).lt(L::splat(1e-18)));
    let (au, av) = (a.inverse_inertia.mul_vec(u), a.inverse_inertia.mul_vec(v));
    let (bu, bv) = (b.inverse_inertia.mul_vec(u), b.inverse_inertia.mul_vec(v));
    let kuu = u.dot(au) + u.dot(bu);
    let kuv = u.dot(av) + u.dot(bv);
    let kvv = v.dot(av) + v.dot(bv);
    let det = kuu * kvv - kuv * kuv;
    let positive = det.gt(L::splat(1e-20));
    let active = big & positive;
    let inverse_det = L::splat(1.0) / positive.select(det, L::splat(1.0));
    let (lu, lv) = (
        (kvv * eu - kuv * ev) * inverse_det,
        (kuu * ev - kuv * eu) * inverse_det,
    );
    a.rotate_preview_where(active & mask_a, -(au.scale(lu) + av.scale(lv)));
    b.rotate_preview_where(active & mask_b, bu.scale(lu) + bv.scale(lv));
}
