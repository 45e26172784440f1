//! Records one path's blocks (a [`PathObserver`]) as a compact event list for the lockstep replay.

use crate::cpu::observe::PathObserver;

/// Events: a leaf is its tested-positions mask (below [`INNER`]); the rest are markers.
pub const INNER: u32 = 0xffff_fff0;
/// A bounce's closest-hit traversal starts.
pub const CLOSEST: u32 = 0xffff_fff1;
/// A shadow ray's any-hit traversal starts.
pub const SHADOW: u32 = 0xffff_fff2;
/// The closest hit found a primitive; the low byte is its material kind.
pub const HIT: u32 = 0xffff_ff00;

/// Whether an event is a traversal step (inner node or leaf).
pub fn is_step(e: u32) -> bool {
    e == INNER || e < HIT
}

/// Whether an event is a closest hit (`HIT | material kind`).
pub fn is_hit(e: u32) -> bool {
    (HIT..INNER).contains(&e)
}

/// One path's events, appended to a buffer shared by the paths of a subgroup.
#[derive(Default)]
pub struct Recorder {
    pub events: Vec<u32>,
}

impl PathObserver for Recorder {
    fn traversal(&mut self, shadow: bool) {
        self.events.push(if shadow { SHADOW } else { CLOSEST });
    }
    fn inner(&mut self) {
        self.events.push(INNER);
    }
    fn leaf(&mut self, tested: u32) {
        debug_assert!(tested < 1 << 24, "the replay takes leaves of at most 24 primitives");
        self.events.push(tested);
    }
    fn hit(&mut self, material_kind: u32) {
        self.events.push(HIT | material_kind);
    }
}
