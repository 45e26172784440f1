//! The measuring commands: what this device's dispatches cost (`dispatch_cost`), what its
//! memory delivers to a pass (`bandwidth`), and the wavefront's intersect with and without its
//! path-state traffic (`intersect_cost`). Above `method` and `gpu`, which they drive, and
//! beside `report`, whose machine and build records they carry.

pub mod bandwidth;
pub mod dispatch_cost;
pub mod intersect_cost;
