// One dispatch's share of the render; twin of DispatchParams in src/layout.rs.

struct Dispatch {
    pixel_offset: u32,
    pixel_count: u32,
    sample_start: u32,
    sample_count: u32,
}
