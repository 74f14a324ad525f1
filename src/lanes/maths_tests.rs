//! The lanes' transcendental functions against libm and the true values, and every lane type
//! against the portable reference, bit for bit.

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
