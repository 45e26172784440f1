// Slots of the SIMD-efficiency counters (`--instrument`); names in src/gpu/instrument.rs.

const PASS_MEGAKERNEL_BOUNCE: u32 = 0u;       // top of each bounce of the megakernel's loop
const PASS_MEGAKERNEL_MATERIAL: u32 = 1u;     // the megakernel's material dispatch
const PASS_MEGAKERNEL_LAMBERTIAN: u32 = 2u;   // inside each material's branch
const PASS_MEGAKERNEL_METAL: u32 = 3u;
const PASS_MEGAKERNEL_DIELECTRIC: u32 = 4u;
const PASS_MEGAKERNEL_EMISSIVE: u32 = 5u;
const PASS_GENERATE: u32 = 6u;
const PASS_INTERSECT: u32 = 7u;
const PASS_SHADE_LAMBERTIAN: u32 = 8u;
const PASS_SHADE_METAL: u32 = 9u;
const PASS_SHADE_DIELECTRIC: u32 = 10u;
const PASS_SHADE_EMISSIVE: u32 = 11u;
const PASS_SHADE: u32 = 12u;
const PASS_MEGAKERNEL_SHADOW: u32 = 13u;     // the megakernel's shadow rays (--nee on)
const PASS_SHADOW: u32 = 14u;
// Inside the BVH traversal loop (shared/bvh.wgsl): the first of three slots per traversal, one
// per step kind (TRAVERSE_*), counted at every loop iteration, so lanes that left the loop early
// weigh as idle for every step the others still take (work-weighted, unlike the points above).
const PASS_MEGAKERNEL_TRAVERSE: u32 = 15u;        // the megakernel's (and tail's) closest hit
const PASS_MEGAKERNEL_SHADOW_TRAVERSE: u32 = 18u; // its shadow rays' any hit
const PASS_INTERSECT_TRAVERSE: u32 = 21u;
const PASS_SHADOW_TRAVERSE: u32 = 24u;
const PASS_SLOTS: u32 = 27u;

// Step kinds, added to a traversal's first slot.
const TRAVERSE_INNER: u32 = 0u;     // an inner node: both children's boxes
const TRAVERSE_LEAF: u32 = 1u;      // a leaf node
const TRAVERSE_PRIMITIVE: u32 = 2u; // one primitive test in a leaf
