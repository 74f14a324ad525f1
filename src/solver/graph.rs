//! Constraint graph colouring (Box2D v3 `constraint_graph.c`, Rapier `interaction_groups.rs`):
//! rows of one kind that share no dynamic body get the same colour, so a colour's rows can be
//! solved W at a time (SIMD lanes) or on several threads without two of them writing the same
//! body. Fixed and kinematic bodies never move, so any number of rows of a colour may share them.
//!
//! Two colourings, both in the rows' stored order, both followed by a stable reorder by colour,
//! so the result depends only on the input (never on timing or thread count):
//! - [`Order::Kept`], what the solver uses for joints and rods: each row takes the colour after
//!   the last colour of any row before it on the same movable body (level scheduling). Two
//!   rows that share a body are then solved in their stored order, and rows that share none
//!   commute, so solving colour by colour gives exactly the sequential Gauss-Seidel sweep of
//!   the paper's solver, at any lane width. Identical ragdolls fill the colours evenly (the
//!   lanes run across ragdolls). A single chain gets one row per colour and gains nothing from
//!   lanes. With greedy colouring a hanging chain converged visibly slower (`tests/it/chain.rs`
//!   failed with it).
//! - [`Order::Greedy`], Box2D's choice, used for contact points: each row takes the lowest
//!   colour neither of its movable bodies has used yet; a row whose bodies have used all
//!   [`MAX_COLOURS`] - 1 colours goes to the last, the overflow colour, solved one row after
//!   another (a crate under a pile). Contact points come in the broad phase's cell order, which
//!   means nothing physically, so no order is lost. Kept order gave the 1000-ragdoll rain's
//!   19 000 points 183 colours, most of a few rows (solved one by one, each colour a thread
//!   hand-off); greedy gives 10-11 full ones and cut the rain's iterations by 15%.

/// Colours of a greedy colouring; the last is the overflow colour.
pub const MAX_COLOURS: usize = 64;

/// Which colouring (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Order {
    /// Level scheduling in stored order: rows sharing a body keep their order (joints, rods).
    Kept,
    /// Lowest free colour, with an overflow colour (contact points).
    Greedy,
}

/// Rows of one kind sorted by colour: colour `c` is `rows[starts[c]..starts[c + 1]]`.
#[derive(Clone, Debug, Default)]
pub struct Colours {
    /// Start of each colour's rows, plus the end of the last.
    pub starts: Vec<u32>,
    /// The overflow colour, whose rows may share bodies (greedy colouring only).
    pub overflow: Option<usize>,
}

impl Colours {
    /// The row ranges of the colours in solve order (empty colours skipped).
    pub fn ranges(&self) -> impl Iterator<Item = (usize, std::ops::Range<usize>)> + '_ {
        self.starts
            .windows(2)
            .enumerate()
            .map(|(c, w)| (c, w[0] as usize..w[1] as usize))
            .filter(|(_, r)| !r.is_empty())
    }

    /// Whether colour `c` is the overflow colour (rows in it may share bodies).
    pub fn is_overflow(&self, c: usize) -> bool {
        self.overflow == Some(c)
    }

    /// Number of non-empty colours.
    pub fn count(&self) -> usize {
        self.ranges().count()
    }
}

/// Reused storage for colouring, so a warmed-up step does not allocate.
#[derive(Clone, Debug, Default)]
pub struct Colouring {
    /// Per body, the colours its rows have used (bit c; greedy), or the next free colour (kept).
    used: Vec<u64>,
    /// Per row, its colour.
    colour_of: Vec<u32>,
    counts: Vec<u32>,
}

impl Colouring {
    /// Colours `rows` (reordering them by colour) and fills `colours`. `bodies_of` gives a
    /// row's two body indices, `movable[i]` whether body i can move. `scratch` is reused space
    /// of the same row type: the rows are placed into it by colour and the two swapped, so each
    /// row is copied once (the rain's 20 000 contact points are 3.5 MB).
    #[allow(clippy::too_many_arguments)]
    pub fn colour<T: Copy>(
        &mut self,
        order: Order,
        rows: &mut Vec<T>,
        scratch: &mut Vec<T>,
        colours: &mut Colours,
        movable: &[bool],
        bodies_of: impl Fn(&T) -> (u32, u32),
    ) {
        self.used.clear();
        self.used.resize(movable.len(), 0);
        self.colour_of.clear();
        self.counts.clear();
        for row in rows.iter() {
            let (a, b) = bodies_of(row);
            let (a, b) = (a as usize, b as usize);
            let (ma, mb) = (movable[a], movable[b]);
            let at = |used: &Vec<u64>, i: usize, m: bool| if m { used[i] } else { 0 };
            let colour = match order {
                Order::Kept => {
                    let colour = at(&self.used, a, ma).max(at(&self.used, b, mb));
                    for (i, m) in [(a, ma), (b, mb)] {
                        if m {
                            self.used[i] = colour + 1;
                        }
                    }
                    colour as usize
                }
                Order::Greedy => {
                    let taken = at(&self.used, a, ma) | at(&self.used, b, mb);
                    // the lowest free colour among the first 63; the overflow colour otherwise
                    let colour = (taken.trailing_ones() as usize).min(MAX_COLOURS - 1);
                    if colour < MAX_COLOURS - 1 {
                        for (i, m) in [(a, ma), (b, mb)] {
                            if m {
                                self.used[i] |= 1 << colour;
                            }
                        }
                    }
                    colour
                }
            };
            if self.counts.len() <= colour {
                self.counts.resize(colour + 1, 0);
            }
            self.colour_of.push(colour as u32);
            self.counts[colour] += 1;
        }
        colours.overflow =
            (order == Order::Greedy && self.counts.len() == MAX_COLOURS).then_some(MAX_COLOURS - 1);
        colours.starts.clear();
        colours.starts.push(0);
        let mut total = 0;
        for count in self.counts.iter_mut() {
            let start = total;
            total += *count;
            colours.starts.push(total);
            *count = start; // now the next free slot of this colour
        }
        scratch.clear();
        scratch.reserve(rows.len());
        let places = &mut scratch.spare_capacity_mut()[..rows.len()];
        for (row, &colour) in rows.iter().zip(&self.colour_of) {
            let slot = &mut self.counts[colour as usize];
            places[*slot as usize].write(*row);
            *slot += 1;
        }
        // SAFETY: the slots of the colours partition 0..rows.len() (each colour's run starts
        // where the last one's ends and holds its count), so every place was written once
        unsafe { scratch.set_len(rows.len()) };
        std::mem::swap(rows, scratch);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Colours body-pair rows in place.
    fn colour(order: Order, rows: &mut Vec<(u32, u32)>, movable: &[bool]) -> Colours {
        let (mut scratch, mut colours) = (Vec::new(), Colours::default());
        let pair = |r: &(u32, u32)| *r;
        Colouring::default().colour(order, rows, &mut scratch, &mut colours, movable, pair);
        colours
    }

    #[test]
    fn greedy_chain_alternates_and_no_colour_shares_a_movable_body() {
        // a chain 0-1-2-3-4 hung from fixed body 5, plus two rows on the fixed body only
        let movable = [true, true, true, true, true, false];
        let mut rows: Vec<(u32, u32)> = vec![(5, 0), (0, 1), (1, 2), (2, 3), (3, 4), (5, 4)];
        let colours = colour(Order::Greedy, &mut rows, &movable);
        for (_, range) in colours.ranges() {
            let mut seen = [false; 6];
            for &(a, b) in &rows[range] {
                for body in [a, b] {
                    if movable[body as usize] {
                        assert!(!seen[body as usize], "body {body} twice in a colour");
                        seen[body as usize] = true;
                    }
                }
            }
        }
        assert_eq!(colours.count(), 2, "a chain needs two colours: {rows:?}");
        assert_eq!(rows.len(), 6);
    }

    #[test]
    fn a_hub_overflows_into_the_last_colour() {
        let movable = vec![true; 101];
        let mut rows: Vec<(u32, u32)> = (0..100).map(|i| (100, i)).collect();
        let colours = colour(Order::Greedy, &mut rows, &movable);
        let overflow = colours.starts[MAX_COLOURS] - colours.starts[MAX_COLOURS - 1];
        assert_eq!(overflow, 100 - (MAX_COLOURS as u32 - 1));
        assert!(colours.is_overflow(MAX_COLOURS - 1));
    }

    /// Kept order: rows sharing a body keep their stored order; two chains share colours.
    #[test]
    fn kept_order_keeps_each_bodys_rows_in_stored_order() {
        let movable = [true, true, true, true, true, true, false];
        // chain a: 6-0-1-2, chain b: 6-3-4-5, interleaved as two builders would not, but legal
        let stored: Vec<(u32, u32)> = vec![(6, 0), (0, 1), (6, 3), (1, 2), (3, 4), (4, 5)];
        let mut rows = stored.clone();
        let colours = colour(Order::Kept, &mut rows, &movable);
        let position = |r: (u32, u32)| rows.iter().position(|x| *x == r).unwrap();
        for (i, x) in stored.iter().enumerate() {
            for y in &stored[i + 1..] {
                let shares = [x.0, x.1]
                    .iter()
                    .any(|b| movable[*b as usize] && (*b == y.0 || *b == y.1));
                if shares {
                    assert!(
                        position(*x) < position(*y),
                        "{x:?} must stay before {y:?}: {rows:?}"
                    );
                }
            }
        }
        assert_eq!(
            colours.count(),
            3,
            "two chains of three share three colours: {rows:?}"
        );
        assert_eq!(colours.overflow, None);
    }
}
