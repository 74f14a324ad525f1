//! The scalar code's own arithmetic on lanes, to the bit, where the SIMD solver must compute a
//! per-substep constant exactly as the scalar reference does: glam's quaternion product in its
//! SSE2 operation order, and the `atan2f` of the C library this project is built against
//! (glibc's up to 2.40, which is fdlibm's float algorithm: a reduction of the argument to one
//! of five ranges, then an odd and an even polynomial, with glibc's cut to pi / 2 at 2^25;
//! fdlibm is Sun Microsystems' 1993 code, freely licensed; checked against glibc 2.36's
//! machine code). The joints' starting twist ([`start_twist`]) was computed lane by lane with
//! the scalar calls, a tenth of the 1000-ragdoll rain's integrate phase.
//!
//! Lanes the polynomial path does not cover (zero, subnormal, infinite or NaN inputs, ratios
//! past 2^59) fall back to the C library per lane, so the result is the library's for every
//! input. Against another C library (a correctly rounded `atan2f`, as glibc has from 2.41) the
//! scalar solver's bits differ from these, as they would anyway between two such machines;
//! `tests` compare these lanes with the library on millions of inputs.

use super::{not, Lane, Q};
use crate::math::wrap_angle;

/// glam's `Quat * Quat` (`mul_quat` of its SSE2 build) per lane: each component the sum of two
/// partial sums, as the 4-wide shuffles add them.
#[inline(always)]
pub fn quat_mul<L: Lane>(l: Q<L>, r: Q<L>) -> Q<L> {
    Q {
        x: (l.w * r.x + l.x * r.w) + (l.y * r.z - l.z * r.y),
        y: (l.w * r.y - l.x * r.z) + (l.y * r.w + l.z * r.x),
        z: (l.w * r.z + l.x * r.y) + (-(l.y * r.x) + l.z * r.w),
        w: (l.w * r.w - l.x * r.x) + (-(l.y * r.y) - l.z * r.z),
    }
}

/// fdlibm's `atan` of a non-negative `t` (the library's `atanf` for `t >= 0`): the reduction to
/// one of five ranges around 0, 0.5, 1, 1.5 and infinity, then the odd and even polynomials.
/// Valid for finite `t >= 0`.
#[inline(always)]
fn atan_positive<L: Lane>(t: L) -> L {
    // the library's constants as its C source writes them (double literals rounded to float)
    const ATAN_HI: [f32; 4] = [
        4.6364760399e-01_f64 as f32,
        7.8539812565e-01_f64 as f32,
        9.8279368877e-01_f64 as f32,
        1.5707962513e+00_f64 as f32,
    ];
    const ATAN_LO: [f32; 4] = [
        5.0121582440e-09_f64 as f32,
        3.7748947079e-08_f64 as f32,
        3.4473217170e-08_f64 as f32,
        7.5497894159e-08_f64 as f32,
    ];
    const T: [f32; 11] = [
        3.3333334327e-01_f64 as f32,
        -2.0000000298e-01_f64 as f32,
        1.4285714924e-01_f64 as f32,
        -1.1111110449e-01_f64 as f32,
        9.0908870101e-02_f64 as f32,
        -7.6918758452e-02_f64 as f32,
        6.6610731184e-02_f64 as f32,
        -5.8335702866e-02_f64 as f32,
        4.9768779427e-02_f64 as f32,
        -3.6531571299e-02_f64 as f32,
        1.6285819933e-02_f64 as f32,
    ];
    let s = L::splat;
    let one = s(1.0);
    // the ranges: |t| < 0.4375 (none), < 0.6875 (0.5), < 1.1875 (1), < 2.4375 (1.5), else inf
    let (r0, r1, r2, r3) = (
        t.lt(s(0.4375)),
        t.lt(s(0.6875)),
        t.lt(s(1.1875)),
        t.lt(s(2.4375)),
    );
    // the reduced argument as one division of the range's numerator by its denominator
    let numerator = r1.select(
        s(2.0) * t - one,
        r2.select(t - one, r3.select(t - s(1.5), s(-1.0))),
    );
    let denominator = r1.select(
        s(2.0) + t,
        r2.select(t + one, r3.select(one + s(1.5) * t, t)),
    );
    let x = r0.select(t, numerator / denominator);
    let z = x * x;
    let w = z * z;
    let s1 = z
        * (s(T[0]) + w * (s(T[2]) + w * (s(T[4]) + w * (s(T[6]) + w * (s(T[8]) + w * s(T[10]))))));
    let s2 = w * (s(T[1]) + w * (s(T[3]) + w * (s(T[5]) + w * (s(T[7]) + w * s(T[9])))));
    let pick = |table: [f32; 4]| {
        r1.select(
            s(table[0]),
            r2.select(s(table[1]), r3.select(s(table[2]), s(table[3]))),
        )
    };
    let reduced = pick(ATAN_HI) - ((x * (s1 + s2) - pick(ATAN_LO)) - x);
    let small = x - x * (s1 + s2);
    // below 2^-29 the library returns t itself, from 2^25 on its pi / 2
    let huge = s(ATAN_HI[3]) + s(ATAN_LO[3]);
    let result = t
        .lt(s(2f32.powi(25)))
        .select(r0.select(small, reduced), huge);
    t.lt(s(2f32.powi(-29))).select(t, result)
}

/// The library's `atan2f(y, x)` per lane (fdlibm's `__ieee754_atan2f` over `atan_positive`).
#[inline(always)]
pub fn atan2<L: Lane>(y: L, x: L) -> L {
    const PI: f32 = 3.1415927410e+00_f64 as f32;
    const PI_LO: f32 = -8.7422776573e-08_f64 as f32;
    let s = L::splat;
    let (ax, ay) = (x.abs(), y.abs());
    // lanes for the library: zero, subnormal, infinite or NaN inputs, ratios past 2^59 (the
    // library's own cut is at 2^60, so these cover it)
    let normal = |v: L| s(f32::MIN_POSITIVE).le(v) & v.lt(s(f32::INFINITY));
    let scale = s(2f32.powi(59));
    let plain = normal(ax) & normal(ay) & ay.le(scale * ax) & ax.le(scale * ay);
    let t = plain.select(ay / ax, s(1.0));
    let z = atan_positive(t);
    // the quadrant: (+, +) z, (-, +) -z, (+, -) pi - (z - pi_lo), (-, -) (z - pi_lo) - pi
    let negative_x = x.lt(s(0.0));
    let negative_y = y.lt(s(0.0));
    let right = negative_y.select(-z, z);
    let left = negative_y.select((z - s(PI_LO)) - s(PI), s(PI) - (z - s(PI_LO)));
    let result = negative_x.select(left, right);
    if !not(plain).any() {
        return result;
    }
    L::from_fn(|i| match plain.at(i).to_bits() != 0 {
        true => result.at(i),
        false => y.at(i).atan2(x.at(i)),
    })
}

/// [`crate::math::twist_angle`] about x of `frame_a^-1 frame_b` per lane, the joints' starting
/// twist ([`crate::constraint::AngularLimit::start_twist`]), to the bit.
#[inline(always)]
pub fn start_twist<L: Lane>(frame_a: Q<L>, frame_b: Q<L>) -> L {
    let q = quat_mul(frame_a.conjugate(), frame_b);
    // glam's `Vec3::dot` with the x axis, with its additions of signed zeros
    let projection = (q.x * L::splat(1.0) + q.y * L::splat(0.0)) + q.z * L::splat(0.0);
    let angle = L::splat(2.0) * atan2(projection, q.w);
    // `wrap_angle`: below a full turn its `a % TAU` is `a` itself; a full turn (or NaN) takes
    // the scalar function, whose remainder keeps the sign of a zero
    let (pi, tau) = (
        L::splat(std::f32::consts::PI),
        L::splat(std::f32::consts::TAU),
    );
    let wrapped = angle
        .gt(pi)
        .select(angle - tau, angle.lt(-pi).select(angle + tau, angle));
    let within = angle.abs().lt(tau);
    if !not(within).any() {
        return wrapped;
    }
    L::from_fn(|i| match within.at(i).to_bits() != 0 {
        true => wrapped.at(i),
        false => wrap_angle(angle.at(i)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraint::AngularLimit;
    use crate::math::Quat;

    type W = wide::f32x16;

    /// Whether the C library's `atan2f` is the one these lanes reproduce (glibc up to 2.40): on
    /// an input where its cut to pi / 2 and a correctly rounded `atan2f` (glibc 2.41 on, musl
    /// differs again) give neighbouring floats. Elsewhere the bit-for-bit tests have nothing
    /// to compare with, and say so.
    fn library_is_fdlibms() -> bool {
        let (y, x) = std::hint::black_box((1.2028361e8f32, 2.8911562f32));
        let fdlibm = y.atan2(x).to_bits() == 0x3fc9_0fdb;
        if !fdlibm {
            eprintln!("the C library's atan2f is not fdlibm's: the lanes are not compared");
        }
        fdlibm
    }

    /// A deterministic stream of floats (xorshift): uniform in `[-range, range]`.
    fn floats(seed: u64, range: f32) -> impl FnMut() -> f32 {
        let mut state = seed;
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            range * ((state >> 40) as f32 / (1u64 << 23) as f32 * 2.0 - 1.0)
        }
    }

    fn same_bits(
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

    /// Two million pairs over the whole float range that matters (quaternion components in
    /// [-1, 1], then ratios up to 2^40 and down to 2^-40), the special values, and the five
    /// ranges' edges: every lane is the library's `atan2f`, to the bit.
    #[test]
    fn atan2_is_the_librarys_to_the_bit() {
        if !library_is_fdlibms() {
            return;
        }
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
                atan2(y, x),
                |i| y.at(i).atan2(x.at(i)),
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
            2f32.powi(25),
            2f32.powi(34),
            2f32.powi(-29),
            2f32.powi(60),
            3.0e38,
        ];
        for &y in &special {
            for &x in &special {
                for sign in [1.0, -1.0] {
                    let (yl, xl) = (W::splat(sign * y), W::splat(x));
                    let scalar = (sign * y).atan2(x);
                    same_bits(
                        atan2(yl, xl),
                        |_| scalar,
                        &format!("atan2({}, {x})", sign * y),
                        |_| String::new(),
                    );
                }
            }
        }
        // each range's edges and their neighbours, as ratios over x = 1 and x = 3
        for edge in [
            0.4375f32,
            0.6875,
            1.1875,
            2.4375,
            2f32.powi(25),
            2f32.powi(-29),
        ] {
            for x in [1.0f32, 3.0, -3.0] {
                let y = W::from_fn(|i| f32::from_bits((edge * x.abs()).to_bits() - 8 + i as u32));
                same_bits(
                    atan2(y, W::splat(x)),
                    |i| y.at(i).atan2(x),
                    "edges",
                    |i| format!("{:e}", y.at(i)),
                );
            }
        }
    }

    /// The starting twist in lanes is the scalar `AngularLimit::start_twist`, to the bit, for
    /// random unit frames (and frames a half turn apart, where the twist wraps).
    #[test]
    fn start_twist_is_the_scalar_ones_to_the_bit() {
        if !library_is_fdlibms() {
            return;
        }
        let mut f = floats(3, 1.0);
        let mut unit = || Quat::from_xyzw(f(), f(), f(), f()).normalize();
        for round in 0..20_000 {
            let a: [Quat; 16] = std::array::from_fn(|_| unit());
            let b: [Quat; 16] = std::array::from_fn(|i| match round % 3 {
                0 => unit(),
                1 => a[i] * Quat::from_rotation_x(std::f32::consts::PI + 1e-3 * i as f32),
                _ => a[i],
            });
            let lanes = start_twist(Q::<W>::from_fn(|i| a[i]), Q::<W>::from_fn(|i| b[i]));
            same_bits(
                lanes,
                |i| AngularLimit::start_twist(a[i], b[i]),
                "twist",
                |i| format!("{:?} {:?}", a[i], b[i]),
            );
        }
    }

    #[test]
    fn the_quaternion_product_is_glams_to_the_bit() {
        let mut f = floats(5, 2.0);
        for _ in 0..20_000 {
            let a: [Quat; 16] = std::array::from_fn(|_| Quat::from_xyzw(f(), f(), f(), f()));
            let b: [Quat; 16] = std::array::from_fn(|_| Quat::from_xyzw(f(), f(), f(), f()));
            let q = quat_mul(Q::<W>::from_fn(|i| a[i]), Q::<W>::from_fn(|i| b[i]));
            for i in 0..16 {
                let glam = a[i] * b[i];
                assert_eq!(
                    q.lane(i).to_array().map(f32::to_bits),
                    glam.to_array().map(f32::to_bits),
                    "lane {i}"
                );
            }
        }
    }
}
