//! Splitting a sweep's or a tuning grid's combinations between processes (an array job):
//! shard `i/n` runs the combinations whose index is `i - 1` modulo `n`, so the shards together
//! run each combination exactly once, and interleaving keeps their costs alike.

/// Shard `index` of `count` (1-based), `1/1` runs everything.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// Which shard this is, from 1 to `count`.
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

impl Shard {
    /// The one shard that runs everything.
    pub const ALL: Shard = Shard { index: 1, count: 1 };

    /// Whether this shard runs combination `i` (0-based).
    pub fn takes(self, i: usize) -> bool {
        i % self.count == self.index - 1
    }

    /// `` for the whole run, else `_shard2of3` (file names).
    pub fn suffix(self) -> String {
        if self == Shard::ALL {
            String::new()
        } else {
            format!("_shard{}of{}", self.index, self.count)
        }
    }
}

impl std::str::FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Shard, String> {
        let parsed = s
            .split_once('/')
            .and_then(|(i, n)| Some((i.trim().parse().ok()?, n.trim().parse().ok()?)));
        match parsed {
            Some((index, count)) if count >= 1 && (1..=count).contains(&index) => {
                Ok(Shard { index, count })
            }
            _ => Err(format!(
                "expected I/N with 1 <= I <= N, e.g. 2/3; got \"{s}\""
            )),
        }
    }
}

impl Shard {
    /// The shard a file stem names, `<stem>_shardIofN`, and the stem before it.
    pub fn from_stem(stem: &str) -> Option<(&str, Shard)> {
        let (base, tail) = stem.rsplit_once("_shard")?;
        let (index, count) = tail.split_once("of")?;
        let shard: Shard = format!("{index}/{count}").parse().ok()?;
        Some((base, shard))
    }
}

/// The rows of every shard back in the whole run's order: `shards[s]` holds shard `s + 1` of
/// `shards.len()`, whose rows are combinations `s, s + N, s + 2N, ...` ([`Shard::takes`]).
/// An error says which shard has too many or too few rows for that.
pub fn interleave<T>(shards: Vec<Vec<T>>) -> Result<Vec<T>, String> {
    let count = shards.len();
    let total: usize = shards.iter().map(Vec::len).sum();
    for (s, rows) in shards.iter().enumerate() {
        // combinations s, s + N, ... below the total
        let expected = (total + count - 1 - s) / count;
        if rows.len() != expected {
            return Err(format!(
                "shard {} of {count} has {} rows; with {total} in all it should have {expected}",
                s + 1,
                rows.len()
            ));
        }
    }
    let mut iterators: Vec<_> = shards.into_iter().map(Vec::into_iter).collect();
    Ok((0..total)
        .map(|k| iterators[k % count].next().expect("counted above"))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_interleave_back_into_the_whole_order() {
        let whole: Vec<usize> = (0..11).collect();
        for count in 1..=4 {
            let shards: Vec<Vec<usize>> = (1..=count)
                .map(|index| {
                    let shard = Shard { index, count };
                    whole.iter().copied().filter(|&i| shard.takes(i)).collect()
                })
                .collect();
            assert_eq!(interleave(shards).unwrap(), whole, "{count} shards");
        }
        let short = vec![vec![0, 2, 4], vec![1]];
        let message = interleave(short).unwrap_err();
        assert_eq!(
            message,
            "shard 1 of 2 has 3 rows; with 4 in all it should have 2"
        );
    }

    #[test]
    fn a_stem_names_its_shard() {
        assert_eq!(
            Shard::from_stem("ragdoll_drop_sweep_shard2of8"),
            Some(("ragdoll_drop_sweep", Shard { index: 2, count: 8 }))
        );
        assert_eq!(Shard::from_stem("ragdoll_drop_sweep"), None);
        assert_eq!(Shard::from_stem("x_shard9of8"), None);
    }
}
