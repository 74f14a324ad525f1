//! Body pairs a joint or rod joins (and that do not ask to collide): they never become
//! candidate pairs. Box2D v3 filters joined shapes where a pair is created, as here; testing
//! them at every step's report instead cost the settled 1000-ragdoll rain 9 300 lookups a
//! step, a ninth of its candidates, each after the pair's boxes and gap bound were read.

/// The joined pairs, listed under their lower body index.
#[derive(Clone, Debug, Default)]
pub struct Joined {
    /// The higher bodies of body `i`'s pairs: `higher[start[i]..start[i + 1]]` (a handful).
    start: Vec<u32>,
    higher: Vec<u32>,
    /// Each body's group: the lowest body joined to it through any chain of pairs (a
    /// ragdoll's root). Two bodies of different groups are never joined, which the grid's
    /// sweep tests without a lookup.
    group: Vec<u32>,
}

impl Joined {
    /// The lists for `body_count` bodies and the joined `pairs` (either order).
    pub fn new(body_count: usize, pairs: impl Iterator<Item = (u32, u32)> + Clone) -> Joined {
        let ordered = pairs.map(|(a, b)| (a.min(b), a.max(b)));
        let mut start = vec![0u32; body_count + 1];
        for (low, _) in ordered.clone() {
            start[low as usize + 1] += 1;
        }
        for i in 0..body_count {
            start[i + 1] += start[i];
        }
        let mut higher = vec![0; start[body_count] as usize];
        let mut filled = start.clone();
        // union-find, each set's root its lowest body
        let mut group: Vec<u32> = (0..body_count as u32).collect();
        fn root(group: &mut [u32], mut i: u32) -> u32 {
            while group[i as usize] != i {
                group[i as usize] = group[group[i as usize] as usize];
                i = group[i as usize];
            }
            i
        }
        for (low, high) in ordered {
            higher[filled[low as usize] as usize] = high;
            filled[low as usize] += 1;
            let (a, b) = (root(&mut group, low), root(&mut group, high));
            group[a.max(b) as usize] = a.min(b);
        }
        for i in 0..body_count as u32 {
            group[i as usize] = root(&mut group, i);
        }
        Joined {
            start,
            higher,
            group,
        }
    }

    /// Body `body`'s group: bodies of different groups are never joined. A body beyond the
    /// lists is its own group.
    #[inline]
    pub fn group(&self, body: u32) -> u32 {
        self.group.get(body as usize).copied().unwrap_or(body)
    }

    /// Whether bodies `a` and `b` are joined.
    #[inline]
    pub fn contains(&self, a: u32, b: u32) -> bool {
        let (low, high) = (a.min(b) as usize, a.max(b));
        match self.start.get(low + 1) {
            Some(&end) => self.higher[self.start[low] as usize..end as usize].contains(&high),
            None => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn joined_pairs_are_found_in_either_order_and_no_others() {
        let pairs = [(3, 1), (1, 2), (4, 0), (1, 4)];
        let joined = Joined::new(6, pairs.iter().copied());
        for a in 0..7 {
            for b in 0..7 {
                let expected = pairs.contains(&(a, b)) || pairs.contains(&(b, a));
                assert_eq!(joined.contains(a, b), expected, "({a}, {b})");
            }
        }
        assert!(!Joined::default().contains(0, 1));
    }

    /// Bodies joined through a chain of pairs share a group, the chain's lowest body; others
    /// do not.
    #[test]
    fn a_group_is_a_chain_of_joined_bodies() {
        let joined = Joined::new(8, [(5, 3), (3, 6), (7, 1), (2, 7)].into_iter());
        let groups: Vec<u32> = (0..9).map(|b| joined.group(b)).collect();
        assert_eq!(groups, [0, 1, 1, 3, 4, 3, 3, 1, 8]);
    }
}
