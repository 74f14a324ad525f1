//! Value parsers for the command line's options: each refuses a bad value with a message
//! saying what it must be.

/// Parses a choice the way scene files spell it (the enum's serde names).
pub(crate) fn parse_choice<T: serde::de::DeserializeOwned>(s: &str) -> Result<T, String> {
    use serde::de::IntoDeserializer;
    T::deserialize(s.into_deserializer())
        .map_err(|e: serde::de::value::Error| e.to_string().replace('`', "\""))
}

/// Parses a number and keeps it where `holds`; otherwise says what it must do, e.g. "must be
/// 0 or more, got -1".
fn number_where(s: &str, holds: impl Fn(f32) -> bool, must: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if holds(v) => Ok(v),
        Ok(v) => Err(format!("must {must}, got {v}")),
        Err(e) => Err(e.to_string()),
    }
}

/// A fraction in [0, 1] (alpha_b, alpha_t, warm starting).
pub(super) fn unit_interval(s: &str) -> Result<f32, String> {
    number_where(s, |v| (0.0..=1.0).contains(&v), "lie in [0, 1]")
}

/// A number of 0 or more.
pub(super) fn non_negative(s: &str) -> Result<f32, String> {
    number_where(s, |v| v >= 0.0 && v.is_finite(), "be 0 or more")
}

/// A positive, finite time step (s).
pub(super) fn positive_seconds(s: &str) -> Result<f32, String> {
    let holds = |v: f32| v > 0.0 && v.is_finite();
    number_where(s, holds, "be a positive number of seconds")
}

/// A positive, finite stiffness (N m/rad).
pub(super) fn positive_stiffness(s: &str) -> Result<f32, String> {
    let holds = |v: f32| v > 0.0 && v.is_finite();
    number_where(s, holds, "be a positive stiffness in N m/rad")
}

/// A positive speed (m/s), or inf for no limit.
pub(super) fn positive_speed(s: &str) -> Result<f32, String> {
    number_where(s, |v| v > 0.0, "be a positive speed in m/s (or inf)")
}

/// A positive angular speed (rad/s), or inf for no limit.
pub(super) fn positive_angular_speed(s: &str) -> Result<f32, String> {
    number_where(
        s,
        |v| v > 0.0,
        "be a positive angular speed in rad/s (or inf)",
    )
}

/// A contact stacking rate (1/m) from 0 to the scene bound.
pub(super) fn stacking_rate(s: &str) -> Result<f32, String> {
    let max = crate::scene::MAX_CONTACT_STACKING;
    let must = format!("be a rate from 0 to {max} per metre");
    number_where(s, |v| (0.0..=max).contains(&v), &must)
}

/// A cap on stacking's mass ratio: 1 or more (or inf).
pub(super) fn stacking_ratio(s: &str) -> Result<f32, String> {
    number_where(s, |v| v >= 1.0, "be a mass ratio of 1 or more (or inf)")
}

/// Layout seeds: numbers and inclusive ranges, comma separated (`1-16,20`); at most 100 000.
pub(super) fn seed_list(s: &str) -> Result<SeedList, String> {
    let mut seeds = Vec::new();
    for item in s.split(',').map(str::trim) {
        let number = |t: &str| {
            (t.trim().parse::<u64>()).map_err(|_| format!("`{t}` is not a seed (a whole number)"))
        };
        match item.split_once('-') {
            Some((first, last)) => {
                let (first, last) = (number(first)?, number(last)?);
                if last < first || last - first >= 100_000 {
                    return Err(format!("`{item}` is not a range of up to 100000 seeds"));
                }
                seeds.extend(first..=last);
            }
            None => seeds.push(number(item)?),
        }
        if seeds.len() > 100_000 {
            return Err("more than 100000 seeds".into());
        }
    }
    Ok(SeedList(seeds))
}

/// The seeds `--seeds` lists, in order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SeedList(pub Vec<u64>);
