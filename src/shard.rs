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
