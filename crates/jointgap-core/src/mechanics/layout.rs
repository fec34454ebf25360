//! Where each moving body's coordinates sit in the state: per body, the address and size
//! of its positions in `q` and of its velocities in `v` (as MuJoCo's `qpos`/`qvel`
//! addresses). The body kind says the sizes: a planar body has 3 and 3 (x, y, phi); a
//! spatial body will have 7 and 6 (position and unit quaternion; velocity and angular
//! velocity). Nothing else in the engine writes a body's address.

use std::ops::Range;

/// The `N` entries of `x` from `at`, as an array: one body's block of a vector over all
/// coordinates, sized by its kind.
#[inline]
pub fn block<T, const N: usize>(x: &[T], at: usize) -> &[T; N] {
    x[at..at + N].try_into().expect("a block of N entries")
}

/// [`block`], to write.
#[inline]
pub fn block_mut<T, const N: usize>(x: &mut [T], at: usize) -> &mut [T; N] {
    (&mut x[at..at + N]).try_into().expect("a block of N entries")
}

/// The coordinate counts of one body kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BodyShape {
    /// Position coordinates.
    pub nq: usize,
    /// Velocity coordinates (and generalized forces, accelerations).
    pub nv: usize,
}

/// One body's place in the state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BodySlot {
    /// First position coordinate in `q`.
    pub q_at: usize,
    /// First velocity coordinate in `v` (and in `qe`, `qdd`).
    pub v_at: usize,
    /// Its body kind's sizes.
    pub shape: BodyShape,
}

impl BodySlot {
    /// The body's positions in `q`.
    #[inline]
    pub fn q(&self) -> Range<usize> {
        self.q_at..self.q_at + self.shape.nq
    }

    /// The body's velocities in `v` (and its entries of `qe`, `qdd`, `M^-1`).
    #[inline]
    pub fn v(&self) -> Range<usize> {
        self.v_at..self.v_at + self.shape.nv
    }
}

/// The state's layout: every moving body's slot, in body order, packed.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Layout {
    slots: Vec<BodySlot>,
    nq: usize,
    nv: usize,
}

impl Layout {
    /// Bodies of the given kinds, in order, each after the one before.
    pub fn new(shapes: impl IntoIterator<Item = BodyShape>) -> Self {
        let mut layout = Layout::default();
        for shape in shapes {
            layout.slots.push(BodySlot { q_at: layout.nq, v_at: layout.nv, shape });
            layout.nq += shape.nq;
            layout.nv += shape.nv;
        }
        layout
    }

    /// Length of `q`.
    #[inline]
    pub fn nq(&self) -> usize {
        self.nq
    }

    /// Length of `v`.
    #[inline]
    pub fn nv(&self) -> usize {
        self.nv
    }

    /// Body `k`'s slot.
    #[inline]
    pub fn slot(&self, k: usize) -> BodySlot {
        self.slots[k]
    }

    /// Every body's slot, in body order.
    pub fn slots(&self) -> &[BodySlot] {
        &self.slots
    }
}

/// The bodies' generalized forces `qe` (laid out as `v`), which force elements add to
/// body by body.
pub struct Loads<'a, T = f64> {
    layout: &'a Layout,
    qe: &'a mut [T],
}

impl<'a, T> Loads<'a, T> {
    /// `qe` laid out by `layout`.
    pub fn new(layout: &'a Layout, qe: &'a mut [T]) -> Self {
        Loads { layout, qe }
    }

    /// Body `b`'s generalized forces; `None` for the ground, which takes none.
    #[inline]
    pub fn body(&mut self, b: Option<usize>) -> Option<&mut [T]> {
        b.map(|k| &mut self.qe[self.layout.slot(k).v()])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slots_follow_each_other_with_their_own_sizes() {
        let planar = BodyShape { nq: 3, nv: 3 };
        let spatial = BodyShape { nq: 7, nv: 6 };
        let layout = Layout::new([planar, spatial, planar]);
        assert_eq!((layout.nq(), layout.nv()), (13, 12));
        assert_eq!((layout.slot(1).q(), layout.slot(1).v()), (3..10, 3..9));
        assert_eq!((layout.slot(2).q(), layout.slot(2).v()), (10..13, 9..12));
    }
}
