//! The world's constraint list, stamped so caches built from it know when it changed.
//!
//! The solver's joint and rod rows, their colours and lanes change only when the user edits a
//! constraint or a body wakes or sleeps, so the solver keeps them from frame to frame.
//! [`Constraints`] hands out a new [`Constraints::stamp`] on every
//! mutable borrow, so a cache keyed by the stamp (and the bodies' sleep states) is rebuilt
//! exactly when it may be stale. A stamp is drawn from one counter for the whole process: two
//! lists share a stamp only when one is a clone of the other, unchanged since.
//!
//! Beside the joints and rods the list keeps body pairs that must never collide and are joined
//! by nothing that would filter them: Box2D v3's filter joint, a joint with no rows (a ragdoll
//! keeps its forearms out of its thighs this way, [`crate::ragdoll::SelfContacts`]).

use super::Constraint;
use crate::body::BodyId;
use std::ops::{Deref, DerefMut};
use std::sync::atomic::{AtomicU64, Ordering};

/// The next stamp to hand out.
static NEXT_STAMP: AtomicU64 = AtomicU64::new(1);

fn fresh_stamp() -> u64 {
    NEXT_STAMP.fetch_add(1, Ordering::Relaxed)
}

/// The joints and rods of a world: a `Vec<Constraint>` to read and write (through `Deref`),
/// whose every mutable borrow draws a new stamp.
#[derive(Clone, Debug)]
pub struct Constraints {
    list: Vec<Constraint>,
    /// Body pairs that never collide ([`Self::filter_contacts`]).
    contact_filters: Vec<(BodyId, BodyId)>,
    stamp: u64,
}

impl Constraints {
    /// An identifier of the list's contents (the constraints and the contact filters): equal
    /// stamps mean equal lists.
    pub fn stamp(&self) -> u64 {
        self.stamp
    }

    /// Keeps bodies `a` and `b` from ever colliding, as a joint between them does, without a
    /// joint (Box2D v3's filter joint).
    pub fn filter_contacts(&mut self, a: BodyId, b: BodyId) {
        self.stamp = fresh_stamp();
        self.contact_filters.push((a, b));
    }

    /// The body pairs kept from colliding by [`Self::filter_contacts`].
    pub fn contact_filters(&self) -> &[(BodyId, BodyId)] {
        &self.contact_filters
    }

    /// Every body pair that never collides: those a constraint joins
    /// ([`Constraint::keeps_bodies_apart`]), then the contact filters.
    pub fn pairs_kept_apart(&self) -> impl Iterator<Item = (BodyId, BodyId)> + Clone + '_ {
        let joined = self.list.iter().filter(|c| c.keeps_bodies_apart());
        joined
            .map(Constraint::bodies)
            .chain(self.contact_filters.iter().copied())
    }
}

impl Default for Constraints {
    fn default() -> Self {
        Vec::new().into()
    }
}

impl From<Vec<Constraint>> for Constraints {
    fn from(list: Vec<Constraint>) -> Self {
        Constraints {
            list,
            contact_filters: Vec::new(),
            stamp: fresh_stamp(),
        }
    }
}

impl Deref for Constraints {
    type Target = Vec<Constraint>;
    fn deref(&self) -> &Vec<Constraint> {
        &self.list
    }
}

impl DerefMut for Constraints {
    /// Any mutable borrow may change the list: it gets a new stamp.
    fn deref_mut(&mut self) -> &mut Vec<Constraint> {
        self.stamp = fresh_stamp();
        &mut self.list
    }
}

impl<'a> IntoIterator for &'a Constraints {
    type Item = &'a Constraint;
    type IntoIter = std::slice::Iter<'a, Constraint>;
    fn into_iter(self) -> Self::IntoIter {
        self.list.iter()
    }
}

impl<'a> IntoIterator for &'a mut Constraints {
    type Item = &'a mut Constraint;
    type IntoIter = std::slice::IterMut<'a, Constraint>;
    fn into_iter(self) -> Self::IntoIter {
        self.deref_mut().iter_mut()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_mutable_borrow_draws_a_new_stamp_and_clones_share_theirs() {
        let mut list = Constraints::default();
        let first = list.stamp();
        let _ = list.len();
        assert_eq!(list.stamp(), first, "reading keeps the stamp");
        let copy = list.clone();
        assert_eq!(
            copy.stamp(),
            first,
            "an unchanged clone has the same contents"
        );
        list.clear();
        assert_ne!(list.stamp(), first, "a mutable borrow may have changed it");
        for _ in &mut list {}
        let after_loop = list.stamp();
        assert_ne!(after_loop, first);
        list.filter_contacts(BodyId(0), BodyId(1));
        assert_ne!(
            list.stamp(),
            after_loop,
            "a contact filter is part of the contents"
        );
        assert_eq!(list.contact_filters(), [(BodyId(0), BodyId(1))]);
        let after_loop = list.stamp();
        assert_ne!(
            Constraints::default().stamp(),
            after_loop,
            "a new list has its own"
        );
    }
}
