//! Value parsers for the command line's options: each refuses a bad value with a message
//! saying what it must be.

pub(crate) use crate::solver::declared::parse_choice;

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

/// A positive, finite stiffness (N m/rad).
pub(super) fn positive_stiffness(s: &str) -> Result<f32, String> {
    let holds = |v: f32| v > 0.0 && v.is_finite();
    number_where(s, holds, "be a positive stiffness in N m/rad")
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
