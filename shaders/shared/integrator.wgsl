// The path loop of the megakernel, from any bounce on: the megakernel runs it from the camera
// ray, the wavefront's megakernel tail (wavefront/tail.wgsl) from where its passes left a path.
// Twin of the bounce loop of src/cpu/integrator.rs. Needs scene.wgsl, rng.wgsl and
// instrument.wgsl included before it.

// A path in flight: the ray it traces next and what it has gathered.
struct TracedPath {
    ray: Ray,
    throughput: vec3<f32>,
    radiance: vec3<f32>,
    rays: u32,
    // When the previous hit sampled the lights: this ray's density under the diffuse bounce, for
    // the MIS weight of the emission it may find (0: no light sampling, full weight).
    bsdf_pdf: f32,
    // The primitive the ray leaves (NO_ORIGIN for a camera ray): self-hits are counted against it.
    left: u32,
}

// Traces one bounce of `path`: the ray it holds, what the hit adds, the next ray. Returns false
// when the path has ended (escaped, hit an emitter, was absorbed or lost the roulette); reaching max_depth is the
// caller's test (a path that scatters at the last bounce is counted here as cut). The
// regenerating megakernel (megakernel_regenerate.wgsl) runs it one bounce per iteration so
// that a lane whose path ends can start the next sample at once.
fn trace_bounce(path: ptr<function, TracedPath>, pixel: u32, sample: u32, bounce: u32) -> bool {
    instrument(PASS_MEGAKERNEL_BOUNCE);
    let ray = (*path).ray;
    let throughput = (*path).throughput;
    (*path).rays += 1u;
    instrument_traversal(PASS_MEGAKERNEL_TRAVERSE);
    let hit = closest_hit(ray, frame.t_min);
    if hit.prim == NO_HIT {
        (*path).radiance += throughput * background(ray.dir);
        return false;
    }
    if is_self_hit((*path).left, hit.prim, ray, hit.t) {
        count_failure(FAILURE_SELF_HIT);
    }
    let prim = primitive(hit.prim);
    let material = materials[prim.material];
    instrument(PASS_MEGAKERNEL_MATERIAL);
    // Lanes active inside each material's branch: the divergence the wavefront removes.
    switch material.kind {
        case MATERIAL_LAMBERTIAN: { instrument(PASS_MEGAKERNEL_LAMBERTIAN); }
        case MATERIAL_METAL: { instrument(PASS_MEGAKERNEL_METAL); }
        case MATERIAL_DIELECTRIC: { instrument(PASS_MEGAKERNEL_DIELECTRIC); }
        default: { instrument(PASS_MEGAKERNEL_EMISSIVE); }
    }
    let sp = surface_point(prim, ray, hit.t);
    let p = sp.p;
    if material_is(material.kind, MATERIAL_EMISSIVE) {
        var w = 1.0;
        if (*path).bsdf_pdf > 0.0 {
            w = emission_weight(hit.prim, ray.origin, p, ray.dir, hit.t, (*path).bsdf_pdf);
        }
        (*path).radiance += throughput * material.color * w;
        return false;
    }
    let outward = outward_normal(prim, p);
    let front_face = dot(ray.dir, outward) < 0.0;
    let normal = select(-outward, outward, front_face);
    let u = uniform4(pixel, sample, bounce, PURPOSE_SCATTER, frame.seed);
    let uv = surface_texture_uv(material, hit.prim, prim, p);
    let s = scatter(material, ray, texture_point(p), uv, normal, front_face, u);
    if !s.ok {
        return false;
    }
    // Both rays leave to the side the normal faces, so they share the origin (as on the CPU).
    let origin = spawn_origin(sp, outward, s.dir);
    // Direct light at diffuse hits, when the ray it stands in for is within the depth limit.
    let lights_sampled = NEE && material_is(material.kind, MATERIAL_LAMBERTIAN) && bounce + 2u <= frame.max_depth;
    (*path).bsdf_pdf = 0.0;
    if lights_sampled {
        (*path).bsdf_pdf = diffuse_pdf(dot(normal, s.dir));
        let shadow = next_event(p, normal, uniform4(pixel, sample, bounce, PURPOSE_LIGHT, frame.seed));
        if shadow.ok {
            instrument(PASS_MEGAKERNEL_SHADOW);
            (*path).rays += 1u;
            let shadow_ray = Ray(origin, shadow.ray.dir);
            instrument_traversal(PASS_MEGAKERNEL_SHADOW_TRAVERSE);
            if shadow_unblocked(shadow_ray, shadow.t_max, shadow.light, hit.prim) {
                (*path).radiance += throughput * s.attenuation * shadow.weight;
            }
        }
    }
    (*path).throughput = throughput * s.attenuation;
    (*path).ray = Ray(origin, s.dir);
    (*path).left = hit.prim;
    if bounce + 1u >= frame.max_depth {
        count_failure(FAILURE_DEPTH_CUT);
    } else if ROULETTE {
        // After this hit's shadow ray, before the next ray; not at the last bounce (a depth cut
        // either way), as on the CPU.
        let u_rr = uniform4(pixel, sample, bounce, PURPOSE_ROULETTE, frame.seed).x;
        let rr = roulette((*path).throughput, bounce, u_rr);
        if !rr.ok {
            return false;
        }
        (*path).throughput = rr.throughput;
    }
    return true;
}

// Traces `path` from bounce `first` until it ends: escapes, hits an emitter, is absorbed or
// reaches max_depth rays.
fn continue_path(path: ptr<function, TracedPath>, pixel: u32, sample: u32, first: u32) {
    for (var bounce = first; bounce < frame.max_depth; bounce++) {
        if !trace_bounce(path, pixel, sample, bounce) {
            break;
        }
    }
}
