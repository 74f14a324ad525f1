//! The lanes' transcendental functions, written with the [`Lane`] operations only (add,
//! subtract, multiply, divide, compare, select; nothing fused, nothing estimated), so every lane
//! type and width gives the same bits.
//!
//! - [`atan2`], the kernels': Agner Fog's vector class library's method, one division.
//! - [`atan2_libm`] is the `libm` crate's `atan2f` (FreeBSD's, after Sun's fdlibm of 1993) to
//!   the bit, the function the scalar code calls ([`crate::math::atan2`]), for the lanes that
//!   must give the scalar code's bits: its reduction of the argument to one of five ranges,
//!   then odd and even polynomials. Lanes it does not cover (infinite, NaN or subnormal inputs)
//!   take the library per lane.
//! - [`sin_cos`] reduces by pi/2 in three parts (Cody and Waite) and evaluates Cephes' `sinf`
//!   and `cosf` polynomials; within about 2 ulp of the true values up to 6000 rad, past which
//!   lanes take the library.
//! - [`exp`] is Cephes' `expf`: `2^n e^r` with `|r| <= ln 2 / 2` and a degree-6 polynomial.

// The constants are written as the libraries they come from write them (libm's, Cephes'), in
// decimal with more digits than an f32 holds; each rounds to the float those libraries use.
#![allow(clippy::excessive_precision)]

use super::{not, Lane};

/// `libm::atanf` of a finite `t >= 0`.
#[inline(always)]
fn atan_positive<L: Lane>(t: L) -> L {
    const ATAN_HI: [f32; 4] = [
        4.6364760399e-01,
        7.8539812565e-01,
        9.8279368877e-01,
        1.5707962513e+00,
    ];
    const ATAN_LO: [f32; 4] = [
        5.0121582440e-09,
        3.7748947079e-08,
        3.4473217170e-08,
        7.5497894159e-08,
    ];
    const A: [f32; 5] = [
        3.3333328366e-01,
        -1.9999158382e-01,
        1.4253635705e-01,
        -1.0648017377e-01,
        6.1687607318e-02,
    ];
    let s = L::splat;
    let one = s(1.0);
    // the ranges: t < 0.4375 (none), < 0.6875 (0.5), < 1.1875 (1), < 2.4375 (1.5), else inf
    let (r0, r1, r2, r3) = (
        t.lt(s(0.4375)),
        t.lt(s(0.6875)),
        t.lt(s(1.1875)),
        t.lt(s(2.4375)),
    );
    // the reduced argument as one division of the range's numerator by its denominator
    let numerator = r1.select(
        s(2.0) * t - one,
        r2.select(t - one, r3.select(t - s(1.5), -one)),
    );
    let denominator = r1.select(
        s(2.0) + t,
        r2.select(t + one, r3.select(one + s(1.5) * t, t)),
    );
    let x = r0.select(t, numerator / denominator);
    let z = x * x;
    let w = z * z;
    let s1 = z * (s(A[0]) + w * (s(A[2]) + w * s(A[4])));
    let s2 = w * (s(A[1]) + w * s(A[3]));
    // (no closures in the lanes' code: a closure's body would compile outside the function
    // `Lane::dispatch` compiled for the lane type's instructions)
    #[inline(always)]
    fn pick<L: Lane>(table: [f32; 4], (r1, r2, r3): (L, L, L)) -> L {
        let s = L::splat;
        r1.select(
            s(table[0]),
            r2.select(s(table[1]), r3.select(s(table[2]), s(table[3]))),
        )
    }
    let ranges = (r1, r2, r3);
    let reduced = pick(ATAN_HI, ranges) - ((x * (s1 + s2) - pick(ATAN_LO, ranges)) - x);
    let small = x - x * (s1 + s2);
    // below 2^-12 the library returns t itself, from 2^26 on atan(inf)'s high part
    let result = t
        .lt(s(2f32.powi(26)))
        .select(r0.select(small, reduced), s(ATAN_HI[3]));
    t.lt(s(2f32.powi(-12))).select(t, result)
}

/// Per lane `atan2(y, x)` (rad), within 4e-7 (2 ulp of pi) of the true angle: Agner Fog's
/// vector class library's method (the octant's ratio, reduced once more past tan(pi/8), and a
/// degree-9 odd polynomial), with one division. The kernels' angles; [`atan2_libm`] where the
/// lanes must give the scalar code's bits.
#[inline(always)]
pub fn atan2<L: Lane>(y: L, x: L) -> L {
    const P: [f32; 4] = [
        8.05374449538e-2,
        -1.38776856032e-1,
        1.99777106478e-1,
        -3.33329491539e-1,
    ];
    let s = L::splat;
    let zero = L::zero();
    let (ax, ay) = (x.abs(), y.abs());
    // the first octant: t = small / large in [0, 1]
    let swap = ay.gt(ax);
    let (large, small) = (swap.select(ay, ax), swap.select(ax, ay));
    // past tan(pi/8) ~ sqrt(2) - 1: atan(t) = pi/4 + atan((t - 1) / (t + 1)), in one division
    let far = small.gt(s(std::f32::consts::SQRT_2 - 1.0) * large) | small.eq(large);
    let numerator = far.select(small - large, small);
    let denominator = far.select(small + large, large);
    // 0 / 0 (both zero) gives NaN, replaced below
    let z = numerator / denominator;
    let zz = z * z;
    let polynomial = ((s(P[0]) * zz + s(P[1])) * zz + s(P[2])) * zz + s(P[3]);
    let mut angle = (polynomial * zz) * z + z + (far & s(std::f32::consts::FRAC_PI_4));
    angle = swap.select(s(std::f32::consts::FRAC_PI_2) - angle, angle);
    angle = (ax.eq(zero) & ay.eq(zero)).select(zero, angle);
    // the quadrant from the signs, those of zeros included
    #[inline(always)]
    fn negative<L: Lane>(v: L) -> L {
        ((v & L::splat(-0.0)) | L::splat(1.0)).lt(L::zero())
    }
    angle = negative(x).select(s(std::f32::consts::PI) - angle, angle);
    negative(y).select(-angle, angle)
}

/// Per lane `atan2(y, x)`, `libm::atan2f` to the bit.
#[inline(always)]
pub fn atan2_libm<L: Lane>(y: L, x: L) -> L {
    const PI: f32 = 3.1415927410e+00;
    const PI_LO: f32 = -8.7422776573e-08;
    let s = L::splat;
    let zero = L::zero();
    let (ax, ay) = (x.abs(), y.abs());
    // finite and not subnormal, or zero: the lanes' cases; the rest take the library
    #[inline(always)]
    fn covered<L: Lane>(v: L) -> L {
        let s = L::splat;
        (s(f32::MIN_POSITIVE).le(v) & v.lt(s(f32::INFINITY))) | v.eq(L::zero())
    }
    let plain = covered(ax) & covered(ay);
    // the signs, with that of a zero: m = 2 sign(x) + sign(y)
    #[inline(always)]
    fn negative<L: Lane>(v: L) -> L {
        ((v & L::splat(-0.0)) | L::splat(1.0)).lt(L::zero())
    }
    let (negative_x, negative_y) = (negative(x), negative(y));
    let t = plain.select(ay / x.abs().max(s(f32::MIN_POSITIVE)), s(1.0));
    let two_26 = s(2f32.powi(26));
    // |y/x| > 2^26: +-pi/2; |y/x| < 2^-26 with x < 0: z = 0; x = 1: atanf(y) itself
    let steep = ay.gt(ax * two_26);
    let flat_left = negative_x & ax.gt(ay * two_26);
    let z = flat_left.select(zero, atan_positive(t));
    let right = negative_y.select(-z, z);
    let left = negative_y.select((z - s(PI_LO)) - s(PI), s(PI) - (z - s(PI_LO)));
    let mut result = negative_x.select(left, right);
    let half_pi = negative_y.select(s(-PI / 2.0), s(PI / 2.0));
    result = steep.select(half_pi, result);
    let x_one_steep = x.eq(s(1.0)) & two_26.le(ay);
    let atan_inf = negative_y.select(s(-1.5707962513e+00), s(1.5707962513e+00));
    result = x_one_steep.select(atan_inf, result);
    // zeros: atan2(+-0, x) is +-0 or +-pi by x's sign, atan2(y, +-0) is +-pi/2
    let y_zero = ay.eq(zero);
    let on_x_axis = negative_x.select(negative_y.select(s(-PI), s(PI)), y);
    result = ax.eq(zero).select(half_pi, result);
    result = y_zero.select(on_x_axis, result);
    if !not(plain).any() {
        return result;
    }
    L::from_fn(|i| match plain.at(i).to_bits() != 0 {
        true => result.at(i),
        false => libm::atan2f(y.at(i), x.at(i)),
    })
}

/// Per lane `(sin x, cos x)`.
#[inline(always)]
pub fn sin_cos<L: Lane>(x: L) -> (L, L) {
    // pi/2 in three parts, the first two short enough that n times them is exact for the
    // quadrants n below 2^12
    const PIO2_1: f32 = 1.5703125;
    const PIO2_2: f32 = 4.837512969970703125e-4;
    const PIO2_3: f32 = 7.54978995489e-8;
    const SIN: [f32; 3] = [-1.6666654611e-1, 8.3321608736e-3, -1.9515295891e-4];
    const COS: [f32; 3] = [
        4.166664568298827e-2,
        -1.388731625493765e-3,
        2.443315711809948e-5,
    ];
    const LIMIT: f32 = 6000.0;
    let s = L::splat;
    let xa = x.abs();
    // the quadrant n (a whole float) and the reduced argument r in [-pi/4, pi/4]
    let n = round(xa * s(std::f32::consts::FRAC_2_PI));
    let r = ((xa - n * s(PIO2_1)) - n * s(PIO2_2)) - n * s(PIO2_3);
    let r2 = r * r;
    let sin_r = (((s(SIN[2]) * r2 + s(SIN[1])) * r2 + s(SIN[0])) * r2) * r + r;
    let cos_r =
        ((s(COS[2]) * r2 + s(COS[1])) * r2 + s(COS[0])) * (r2 * r2) + (s(1.0) - s(0.5) * r2);
    // n mod 4 as a whole float: quadrants 1 and 3 swap sine and cosine; 2 and 3 negate the
    // sine, 1 and 2 the cosine
    let quadrant = n - s(4.0) * round(n * s(0.25) - s(0.375));
    let (one, two, three) = (
        (quadrant - s(1.0)).abs().lt(s(0.5)),
        (quadrant - s(2.0)).abs().lt(s(0.5)),
        (quadrant - s(3.0)).abs().lt(s(0.5)),
    );
    let swap = one | three;
    let negate_sin = quadrant.gt(s(1.5));
    let negate_cos = one | two;
    let sin = swap.select(cos_r, sin_r);
    let cos = swap.select(sin_r, cos_r);
    let sin = negate_sin.select(-sin, sin);
    let cos = negate_cos.select(-cos, cos);
    // sin(-x) = -sin(x)
    let sin = x.lt(L::zero()).select(-sin, sin);
    let covered = xa.lt(s(LIMIT));
    if !not(covered).any() {
        return (sin, cos);
    }
    let sin = L::from_fn(|i| match covered.at(i).to_bits() != 0 {
        true => sin.at(i),
        false => libm::sinf(x.at(i)),
    });
    let cos = L::from_fn(|i| match covered.at(i).to_bits() != 0 {
        true => cos.at(i),
        false => libm::cosf(x.at(i)),
    });
    (sin, cos)
}

/// Per lane `e^x`: 0 below -87.3, infinity above ln(f32::MAX).
#[inline(always)]
pub fn exp<L: Lane>(x: L) -> L {
    // ln 2 in two parts, the first short enough that n times it is exact
    const LN2_HI: f32 = 0.693359375;
    const LN2_LO: f32 = -2.12194440e-4;
    const P: [f32; 6] = [
        1.9875691500e-4,
        1.3981999507e-3,
        8.3334519073e-3,
        4.1665795894e-2,
        1.6666665459e-1,
        5.0000001201e-1,
    ];
    let s = L::splat;
    const HIGH: f32 = 88.72283;
    let (low, high) = (x.lt(s(-87.3)), x.gt(s(HIGH)));
    let clamped = x.max(s(-87.3)).min(s(HIGH));
    let n = round(clamped * s(std::f32::consts::LOG2_E));
    let r = (clamped - n * s(LN2_HI)) - n * s(LN2_LO);
    let p = P[1..].iter().fold(s(P[0]), |p, &c| p * r + s(c));
    let e_r = p * (r * r) + r + s(1.0);
    // 2^128 is past the exponent's range: scaled by 2^127 and then by 2
    let top = n.gt(s(127.0));
    let result = top.select((e_r * (n - s(1.0)).pow2i()) * s(2.0), e_r * n.pow2i());
    low.select(L::zero(), high.select(s(f32::INFINITY), result))
}

/// Per lane, `x` rounded to the nearest whole number (ties to even), for `|x| < 2^22`: adding
/// and taking away 1.5 * 2^23 leaves no bits below the units.
#[inline(always)]
pub fn round<L: Lane>(x: L) -> L {
    let magic = L::splat(12_582_912.0);
    (x + magic) - magic
}

#[cfg(test)]
#[path = "maths_tests.rs"]
pub(super) mod tests;
