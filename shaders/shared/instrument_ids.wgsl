// Slots of the SIMD-efficiency counters (`--instrument`); names in src/gpu/instrument.rs.

#include "shared/kinds.wgsl"

const PASS_MEGAKERNEL_BOUNCE: u32 = 0u;       // top of each bounce of the megakernel's loop
const PASS_MEGAKERNEL_MATERIAL: u32 = 1u;     // the megakernel's material dispatch
// Inside each material's branch, and each kind's shade pass: a slot per kind (shared/kinds.wgsl),
// so a kind more moves the slots after them, named in the same order in instrument.rs.
const PASS_MEGAKERNEL_LAMBERTIAN: u32 = 2u;   // + material kind
const PASS_MEGAKERNEL_METAL: u32 = PASS_MEGAKERNEL_LAMBERTIAN + MATERIAL_METAL;
const PASS_MEGAKERNEL_DIELECTRIC: u32 = PASS_MEGAKERNEL_LAMBERTIAN + MATERIAL_DIELECTRIC;
const PASS_MEGAKERNEL_EMISSIVE: u32 = PASS_MEGAKERNEL_LAMBERTIAN + MATERIAL_EMISSIVE;
const PASS_GENERATE: u32 = PASS_MEGAKERNEL_LAMBERTIAN + MATERIAL_KIND_COUNT;
const PASS_INTERSECT: u32 = PASS_GENERATE + 1u;
const PASS_SHADE_LAMBERTIAN: u32 = PASS_INTERSECT + 1u; // + material kind
const PASS_SHADE_METAL: u32 = PASS_SHADE_LAMBERTIAN + MATERIAL_METAL;
const PASS_SHADE_DIELECTRIC: u32 = PASS_SHADE_LAMBERTIAN + MATERIAL_DIELECTRIC;
const PASS_SHADE_EMISSIVE: u32 = PASS_SHADE_LAMBERTIAN + MATERIAL_EMISSIVE;
const PASS_SHADE: u32 = PASS_SHADE_LAMBERTIAN + MATERIAL_KIND_COUNT;
const PASS_MEGAKERNEL_SHADOW: u32 = PASS_SHADE + 1u; // the megakernel's shadow rays (--nee on)
const PASS_SHADOW: u32 = PASS_SHADE + 2u;
// Inside the BVH traversal loop (shared/bvh.wgsl): the first of three slots per traversal, one
// per step kind (TRAVERSE_*), counted at every loop iteration, so lanes that left the loop early
// weigh as idle for every step the others still take (work-weighted, unlike the points above).
const PASS_MEGAKERNEL_TRAVERSE: u32 = PASS_SHADE + 3u;  // the megakernel's (and tail's) closest hit
const PASS_MEGAKERNEL_SHADOW_TRAVERSE: u32 = PASS_MEGAKERNEL_TRAVERSE + 3u; // its shadow rays' any hit
const PASS_INTERSECT_TRAVERSE: u32 = PASS_MEGAKERNEL_TRAVERSE + 6u;
const PASS_SHADOW_TRAVERSE: u32 = PASS_MEGAKERNEL_TRAVERSE + 9u;
const PASS_SLOTS: u32 = PASS_MEGAKERNEL_TRAVERSE + 12u;

// Step kinds, added to a traversal's first slot.
const TRAVERSE_INNER: u32 = 0u;     // an inner node: both children's boxes
const TRAVERSE_LEAF: u32 = 1u;      // a leaf node
const TRAVERSE_PRIMITIVE: u32 = 2u; // one primitive test in a leaf
