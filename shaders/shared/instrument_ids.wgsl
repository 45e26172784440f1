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
const PASS_SLOTS: u32 = 15u;
