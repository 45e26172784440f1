//! Records one path's blocks (a [`PathObserver`]) as a compact event list for the lockstep replay.

use crate::cpu::observe::PathObserver;

/// Events: a leaf is its tested-positions mask (below [`INNER`]); the rest are markers.
pub const INNER: u16 = 0xfff0;
/// A bounce's closest-hit traversal starts.
pub const CLOSEST: u16 = 0xfff1;
/// A shadow ray's any-hit traversal starts.
pub const SHADOW: u16 = 0xfff2;
/// The closest hit found a primitive; the low byte is its material kind.
pub const HIT: u16 = 0xff00;

/// Whether an event is a traversal step (inner node or leaf).
pub fn is_step(e: u16) -> bool {
    e == INNER || e < HIT
}

/// Whether an event is a closest hit (`HIT | material kind`).
pub fn is_hit(e: u16) -> bool {
    (HIT..INNER).contains(&e)
}

/// One path's events, appended to a buffer shared by the paths of a subgroup.
#[derive(Default)]
pub struct Recorder {
    pub events: Vec<u16>,
}

impl PathObserver for Recorder {
    fn traversal(&mut self, shadow: bool) {
        self.events.push(if shadow { SHADOW } else { CLOSEST });
    }
    fn inner(&mut self) {
        self.events.push(INNER);
    }
    fn leaf(&mut self, tested: u32) {
        debug_assert!(tested < u32::from(HIT), "leaves hold at most 8 primitives");
        self.events.push(tested as u16);
    }
    fn hit(&mut self, material_kind: u32) {
        self.events.push(HIT | material_kind as u16);
    }
}
