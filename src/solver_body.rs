//! The solver's hot body: only what the iteration loop reads and writes, 96 bytes, contiguous.
//! Built from [`Body`] when a substep predicts its preview pose and written back when the
//! substep derives velocities (Box2D v3 `b2BodyState`, Rapier's solver bodies). Names, shapes,
//! velocities and materials stay in the cold [`Body`].

use crate::body::Body;
use crate::math::{rotate_by_small, Mat3, Quat, Vec3};

/// One body as the iteration loop sees it: the preview pose x* of the current substep.
///
/// `repr(C)`, 96 bytes without padding, so the SIMD gather can read it as six groups of four
/// floats and transpose them into lanes ([`crate::lanes::BodyLanes::gather`]).
#[derive(Clone, Copy, Debug, Default)]
#[repr(C)]
pub struct SolverBody {
    /// Preview orientation q* = exp(rotation_correction) predicted (to first order).
    pub orientation: Quat,
    /// Orientation predicted at the substep's start, before any correction.
    pub predicted: Quat,
    /// Preview position p*.
    pub position: Vec3,
    /// Zero for fixed and kinematic bodies: no constraint moves them.
    pub inverse_mass: f32,
    /// Sum of the rotation vectors constraints applied this substep. Summing makes the
    /// corrections commute; applying them one after another would leave second-order turns
    /// (two tilts make a twist) that build up into spin.
    pub rotation_correction: Vec3,
    /// World inverse inertia `R I^-1 R^T` at the predicted orientation (a full matrix: the
    /// struct has room for it within 96 bytes, and it keeps the scalar path's rounding the
    /// same as the body's own).
    pub inverse_inertia: Mat3,
}

const _: () = assert!(std::mem::size_of::<SolverBody>() == 96);
const _: () = assert!(std::mem::align_of::<SolverBody>() == 16);

impl SolverBody {
    /// The body as six groups of four floats: orientation, predicted, (position, inverse mass),
    /// (rotation correction, inverse inertia's first entry), then the inertia's other eight.
    #[inline(always)]
    pub fn as_quads(&self) -> &[[f32; 4]; 6] {
        // SAFETY: repr(C), 96 bytes of f32 fields without padding (asserted above); Quat and
        // Vec3 are plain f32 components.
        unsafe { &*(self as *const SolverBody as *const [[f32; 4]; 6]) }
    }

    /// [`SolverBody::as_quads`], to write.
    #[inline(always)]
    pub fn as_quads_mut(&mut self) -> &mut [[f32; 4]; 6] {
        // SAFETY: as for `as_quads`; every bit pattern is a valid f32.
        unsafe { &mut *(self as *mut SolverBody as *mut [[f32; 4]; 6]) }
    }

    /// The body at its pose, a preview with no correction yet (outside a step: tests, tools).
    pub fn from_body(body: &Body) -> Self {
        SolverBody {
            orientation: body.orientation,
            predicted: body.orientation,
            position: body.position,
            inverse_mass: body.inverse_mass,
            rotation_correction: Vec3::ZERO,
            inverse_inertia: body.inverse_inertia_world(),
        }
    }

    /// Writes the preview back to `body` as its pose (outside a step: tests, tools).
    pub fn write_pose(&self, body: &mut Body) {
        body.position = self.position;
        body.orientation = self.orientation;
        body.update_world_inertia();
    }

    /// World position of a body-space point at the preview pose.
    #[inline(always)]
    pub fn point(&self, local: Vec3) -> Vec3 {
        self.position + self.orientation * local
    }

    #[inline(always)]
    fn rotate_preview(&mut self, dtheta: Vec3) {
        self.rotation_correction += dtheta;
        self.orientation = rotate_by_small(self.predicted, self.rotation_correction);
    }

    /// Applies a positional impulse `impulse` (kg m) at world offset `r` from the centre of
    /// mass to the preview pose: dp = P / m, dtheta = I^-1 (r x P).
    #[inline(always)]
    pub fn apply_positional_impulse(&mut self, impulse: Vec3, r: Vec3) {
        if self.inverse_mass == 0.0 {
            return;
        }
        self.position += impulse * self.inverse_mass;
        let dtheta = self.inverse_inertia * (r.cross(impulse));
        self.rotate_preview(dtheta);
    }

    /// Applies a positional impulse through the centre of mass: dp = P / m.
    #[inline(always)]
    pub fn apply_linear_impulse(&mut self, impulse: Vec3) {
        self.position += impulse * self.inverse_mass;
    }

    /// Applies an angular impulse `l` (kg m^2 rad) to the preview orientation: dtheta = I^-1 l.
    #[inline(always)]
    pub fn apply_angular_impulse(&mut self, l: Vec3) {
        if self.inverse_mass == 0.0 {
            return;
        }
        let dtheta = self.inverse_inertia * (l);
        self.rotate_preview(dtheta);
    }

    /// Generalised inverse mass for a positional correction along unit `n` at offset `r`.
    #[inline(always)]
    pub fn positional_inverse_mass(&self, r: Vec3, n: Vec3) -> f32 {
        let rn = r.cross(n);
        self.inverse_mass + rn.dot(self.inverse_inertia * (rn))
    }

    /// `g . I^-1 g` for an angular direction `g` of any length.
    #[inline(always)]
    pub fn angular_inverse_mass(&self, g: Vec3) -> f32 {
        g.dot(self.inverse_inertia * (g))
    }

    /// Inverse effective mass block of a point at offset `r`: `1/m E - [r] I^-1 [r]`.
    #[inline(always)]
    pub fn point_inverse_mass_matrix(&self, r: Vec3) -> Mat3 {
        let rx = crate::math::skew(r);
        Mat3::from_diagonal(Vec3::splat(self.inverse_mass)) - rx * self.inverse_inertia * rx
    }
}

/// Two distinct entries of a slice, mutably.
#[inline(always)]
pub fn pair_mut<T>(items: &mut [T], a: usize, b: usize) -> (&mut T, &mut T) {
    assert_ne!(a, b, "a constraint needs two distinct bodies");
    if a < b {
        let (lo, hi) = items.split_at_mut(b);
        (&mut lo[a], &mut hi[0])
    } else {
        let (lo, hi) = items.split_at_mut(a);
        (&mut hi[0], &mut lo[b])
    }
}

/// A slice shared by the workers of one colour, whose rows write disjoint elements (the world's
/// bodies in the contacts' velocity pass).
pub struct SharedSlice<T> {
    ptr: *mut T,
    len: usize,
}

// (not derived: a derive would ask `T: Copy`)
impl<T> Clone for SharedSlice<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for SharedSlice<T> {}

// SAFETY: access goes through `ptr`, whose callers guarantee that no element is written by one
// thread while another reads or writes it (graph colouring).
unsafe impl<T: Send> Send for SharedSlice<T> {}
unsafe impl<T: Send> Sync for SharedSlice<T> {}

impl<T> SharedSlice<T> {
    /// Wraps `items`, which must outlive every use of the result.
    pub fn new(items: &mut [T]) -> Self {
        SharedSlice {
            ptr: items.as_mut_ptr(),
            len: items.len(),
        }
    }

    /// Element `i`.
    ///
    /// # Safety
    /// While the pointer is used, no other thread may write element `i`, and no other thread
    /// may read it if it is written through the pointer.
    #[inline(always)]
    pub unsafe fn ptr(&self, i: usize) -> *mut T {
        assert!(i < self.len);
        self.ptr.add(i)
    }
}

/// The solver bodies shared by the workers of one colour. Rows of a colour share no movable
/// body, so each movable body is written by one row at a time; immovable bodies (zero inverse
/// mass) are only read, and a row gets a private copy of them.
#[derive(Clone, Copy)]
pub struct SharedBodies {
    ptr: *mut SolverBody,
    len: usize,
}

// SAFETY: access goes through `with_pair`/`read`/`write`, whose callers guarantee that no two
// concurrent rows touch the same movable body (graph colouring).
unsafe impl Send for SharedBodies {}
unsafe impl Sync for SharedBodies {}

impl SharedBodies {
    /// Wraps `bodies`, which must outlive every use of the result.
    pub fn new(bodies: &mut [SolverBody]) -> Self {
        SharedBodies {
            ptr: bodies.as_mut_ptr(),
            len: bodies.len(),
        }
    }

    /// Runs `f` on bodies `a` and `b`; an immovable one is passed as a copy.
    ///
    /// A solver kernel passes its closure marked `#[inline(always)]`: a closure is a function
    /// of its own, and one not inlined compiles for the baseline's instructions instead of
    /// those of the lane type's dispatched function ([`crate::lanes::Lane::dispatch`]).
    ///
    /// # Safety
    /// No other thread may access the movable ones among `a` and `b` meanwhile.
    #[inline(always)]
    pub unsafe fn with_pair<R>(
        &self,
        a: u32,
        b: u32,
        f: impl FnOnce(&mut SolverBody, &mut SolverBody) -> R,
    ) -> R {
        let (a, b) = (a as usize, b as usize);
        assert!(a < self.len && b < self.len && a != b);
        let (pa, pb) = (self.ptr.add(a), self.ptr.add(b));
        let (mut copy_a, mut copy_b);
        let ra = if (*pa).inverse_mass != 0.0 {
            &mut *pa
        } else {
            copy_a = *pa;
            &mut copy_a
        };
        let rb = if (*pb).inverse_mass != 0.0 {
            &mut *pb
        } else {
            copy_b = *pb;
            &mut copy_b
        };
        f(ra, rb)
    }

    /// A copy of body `i`.
    ///
    /// # Safety
    /// No other thread may be writing body `i`.
    #[inline(always)]
    pub unsafe fn read(&self, i: u32) -> SolverBody {
        assert!((i as usize) < self.len);
        *self.ptr.add(i as usize)
    }

    /// Body `i` as [`SolverBody::as_quads`], to read in place.
    ///
    /// # Safety
    /// No other thread may be writing body `i` while the reference lives.
    #[inline(always)]
    pub unsafe fn quads<'a>(&self, i: u32) -> &'a [[f32; 4]; 6] {
        assert!((i as usize) < self.len);
        (*self.ptr.add(i as usize)).as_quads()
    }

    /// Body `i`, to write.
    ///
    /// # Safety
    /// No other thread may access body `i` meanwhile, and it must be movable.
    #[inline(always)]
    #[allow(clippy::mut_from_ref)]
    pub unsafe fn get_mut(&self, i: u32) -> &mut SolverBody {
        assert!((i as usize) < self.len);
        &mut *self.ptr.add(i as usize)
    }
}
