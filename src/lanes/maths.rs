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
pub(super) mod tests {
    use super::super::{portable::Portable, F32x16, F32x4, F32x8, LaneWidth};
    use super::*;

    /// The reference lane type: plain arrays, runnable on any CPU.
    pub type W = Portable<16>;

    /// A deterministic stream of floats (xorshift): uniform in `[-range, range]`.
    pub fn floats(seed: u64, range: f32) -> impl FnMut() -> f32 {
        let mut state = seed;
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            range * ((state >> 41) as f32 / (1u64 << 23) as f32 * 2.0 - 1.0)
        }
    }

    /// Asserts that each lane of `lanes` has `scalar(i)`'s bits (any NaN matches any NaN).
    pub fn same_bits(
        lanes: W,
        scalar: impl Fn(usize) -> f32,
        what: &str,
        input: impl Fn(usize) -> String,
    ) {
        for i in 0..16 {
            let (l, s) = (lanes.at(i), scalar(i));
            assert!(
                l.to_bits() == s.to_bits() || (l.is_nan() && s.is_nan()),
                "{what}, lane {i}: lanes {l:e} ({:#x}), library {s:e} ({:#x}) [{}]",
                l.to_bits(),
                s.to_bits(),
                input(i)
            );
        }
    }

    /// Two million pairs over the float range that matters (quaternion components in [-1, 1],
    /// then ratios up to 2^40 and down to 2^-40), the special values, and the five ranges'
    /// edges: every lane is `libm::atan2f`, to the bit.
    #[test]
    fn atan2_libm_is_libms_to_the_bit() {
        let mut unit = floats(7, 1.0);
        let mut exponent = floats(11, 40.0);
        for round in 0..125_000 {
            let (y, x): (W, W) = if round % 2 == 0 {
                (W::from_fn(|_| unit()), W::from_fn(|_| unit()))
            } else {
                let y = W::from_fn(|_| unit() * 2f32.powf(exponent()));
                (y, W::from_fn(|_| unit()))
            };
            same_bits(
                atan2_libm(y, x),
                |i| libm::atan2f(y.at(i), x.at(i)),
                "random",
                |i| format!("{:e} {:e} ratio {:e}", y.at(i), x.at(i), y.at(i) / x.at(i)),
            );
        }
        let special = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            f32::MIN_POSITIVE,
            1e-40,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            0.4375,
            0.6875,
            1.1875,
            2.4375,
            2f32.powi(26),
            2f32.powi(27),
            2f32.powi(-12),
            2f32.powi(-26),
            2f32.powi(60),
            3.0e38,
        ];
        for &y in &special {
            for &x in &special {
                for sign in [1.0, -1.0] {
                    let (yl, xl) = (W::splat(sign * y), W::splat(x));
                    let scalar = libm::atan2f(sign * y, x);
                    let what = format!("atan2({}, {x})", sign * y);
                    same_bits(atan2_libm(yl, xl), |_| scalar, &what, |_| String::new());
                }
            }
        }
        // each range's edges and their neighbours, as ratios over x = 1, 3 and -3
        for edge in [
            0.4375f32,
            0.6875,
            1.1875,
            2.4375,
            2f32.powi(26),
            2f32.powi(-12),
        ] {
            for x in [1.0f32, 3.0, -3.0] {
                let y = W::from_fn(|i| f32::from_bits((edge * x.abs()).to_bits() - 8 + i as u32));
                same_bits(
                    atan2_libm(y, W::splat(x)),
                    |i| libm::atan2f(y.at(i), x),
                    "edges",
                    |i| format!("{:e}", y.at(i)),
                );
            }
        }
    }

    /// The kernels' `atan2` within 4e-7 rad (under 2 ulp of pi) of the true angle over every quadrant, ratios
    /// from 2^-40 to 2^40, zeros of either sign, and infinities.
    #[test]
    fn atan2_is_within_a_few_ulp_of_the_true_angle() {
        let mut unit = floats(23, 1.0);
        let mut exponent = floats(29, 40.0);
        let mut worst = 0.0f64;
        for round in 0..50_000 {
            let y = W::from_fn(|_| {
                unit()
                    * if round % 2 == 0 {
                        1.0
                    } else {
                        2f32.powf(exponent())
                    }
            });
            let x = W::from_fn(|_| unit());
            let got = atan2(y, x);
            for i in 0..16 {
                let truth = (y.at(i) as f64).atan2(x.at(i) as f64);
                worst = worst.max((got.at(i) as f64 - truth).abs());
            }
        }
        assert!(worst < 4e-7, "largest error {worst:e}");
        for (y, x) in [
            (0.0f32, 1.0f32),
            (-0.0, 1.0),
            (0.0, -1.0),
            (-0.0, -1.0),
            (0.0, 0.0),
            (-0.0, -0.0),
            (1.0, 0.0),
            (-1.0, -0.0),
            (f32::INFINITY, 1.0),
            (1.0, f32::NEG_INFINITY),
        ] {
            let got = atan2(W::splat(y), W::splat(x)).at(0);
            let want = y.atan2(x);
            assert!(
                (got - want).abs() < 4e-7 && got.is_sign_negative() == want.is_sign_negative(),
                "atan2({y}, {x}): {got} against {want}"
            );
        }
    }

    /// Sine and cosine within 3e-7 of the true values (in f64) for |x| up to 100 rad, and
    /// `libm`'s own past the lanes' range.
    #[test]
    fn sin_cos_are_within_two_ulp_of_the_true_values() {
        let mut angle = floats(13, 100.0);
        let mut worst = 0.0f64;
        for _ in 0..50_000 {
            let x = W::from_fn(|_| angle());
            let (sin, cos) = sin_cos(x);
            for i in 0..16 {
                let (s, c) = (x.at(i) as f64).sin_cos();
                worst = worst.max((sin.at(i) as f64 - s).abs());
                worst = worst.max((cos.at(i) as f64 - c).abs());
            }
        }
        assert!(worst < 3e-7, "largest error {worst:e}");
        let far = W::from_fn(|i| 7000.0 * (i as f32 + 1.0) * if i % 2 == 0 { 1.0 } else { -1.0 });
        let (sin, cos) = sin_cos(far);
        same_bits(
            sin,
            |i| libm::sinf(far.at(i)),
            "far sine",
            |i| format!("{}", far.at(i)),
        );
        same_bits(
            cos,
            |i| libm::cosf(far.at(i)),
            "far cosine",
            |i| format!("{}", far.at(i)),
        );
        let zero = sin_cos(W::splat(0.0));
        assert_eq!((zero.0.at(0), zero.1.at(0)), (0.0, 1.0));
    }

    /// `e^x` within 2e-7 relative over [-87, 88], 0 below -87.3, infinity above 88.73.
    #[test]
    fn exp_is_within_two_ulp_of_the_true_value() {
        let mut t = floats(17, 87.5);
        let mut worst = 0.0f64;
        for _ in 0..50_000 {
            let x = W::from_fn(|_| t() + 0.5);
            let e = exp(x);
            for i in 0..16 {
                let truth = (x.at(i) as f64).exp();
                worst = worst.max((e.at(i) as f64 - truth).abs() / truth);
            }
        }
        assert!(worst < 2e-7, "largest relative error {worst:e}");
        let ends = W::from_fn(|i| [-100.0, -87.2, 88.7, 100.0, 0.0][i % 5]);
        let e = exp(ends);
        assert_eq!(e.at(0), 0.0);
        assert!(e.at(1) > 0.0 && e.at(2).is_finite() && e.at(2) > 3.0e38);
        assert_eq!((e.at(3), e.at(4)), (f32::INFINITY, 1.0));
    }

    /// The functions above, and the basic operations they are made of, on `a` and `b`.
    fn everything<L: Lane>(a: L, b: L) -> [L; 8] {
        let (sin, cos) = sin_cos(a);
        [
            atan2(a, b),
            atan2_libm(a, b),
            sin,
            cos,
            exp(b),
            a.max(b),
            a.min(b) / b.sqrt(),
            a.lt(b).select(a, b),
        ]
    }

    /// Every lane type this CPU runs computes the reference's bits: the functions above, and
    /// the basic operations they are made of.
    #[test]
    fn every_width_gives_the_reference_bits() {
        fn check<L: Lane>() {
            let mut f = floats(19, 10.0);
            for _ in 0..2000 {
                let (a, b): (W, W) = (W::from_fn(|_| f()), W::from_fn(|_| f() * f()));
                let reference = everything(a, b);
                let lanes = |i: usize| -> [L; 2] {
                    [
                        L::from_fn(|k| a.at(i * L::W + k)),
                        L::from_fn(|k| b.at(i * L::W + k)),
                    ]
                };
                for part in 0..16 / L::W {
                    let [la, lb] = lanes(part);
                    let got = everything(la, lb);
                    for (g, r) in got.iter().zip(&reference) {
                        for k in 0..L::W {
                            let (x, y) = (g.at(k), r.at(part * L::W + k));
                            assert!(x.to_bits() == y.to_bits() || x.is_nan() && y.is_nan());
                        }
                    }
                }
            }
        }
        check::<F32x4>();
        if LaneWidth::W8.is_available() {
            check::<F32x8>();
        }
        if LaneWidth::W16.is_available() {
            check::<F32x16>();
        }
    }
}
