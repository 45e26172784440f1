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
}

// Traces `path` from bounce `first` until it ends: escapes, hits an emitter, is absorbed or
// reaches max_depth rays.
fn continue_path(path: ptr<function, TracedPath>, pixel: u32, sample: u32, first: u32) {
    var ray = (*path).ray;
    var throughput = (*path).throughput;
    var radiance = (*path).radiance;
    var rays = (*path).rays;
    var bsdf_pdf = (*path).bsdf_pdf;
    for (var bounce = first; bounce < frame.max_depth; bounce++) {
        instrument(PASS_MEGAKERNEL_BOUNCE);
        rays += 1u;
        let hit = closest_hit(ray, T_MIN);
        if hit.prim == NO_HIT {
            radiance += throughput * background(ray.dir);
            break;
        }
        let prim = primitives[hit.prim];
        let material = materials[prim.material];
        instrument(PASS_MEGAKERNEL_MATERIAL);
        // Lanes active inside each material's branch: the divergence the wavefront removes.
        switch material.kind {
            case MATERIAL_LAMBERTIAN: { instrument(PASS_MEGAKERNEL_LAMBERTIAN); }
            case MATERIAL_METAL: { instrument(PASS_MEGAKERNEL_METAL); }
            case MATERIAL_DIELECTRIC: { instrument(PASS_MEGAKERNEL_DIELECTRIC); }
            default: { instrument(PASS_MEGAKERNEL_EMISSIVE); }
        }
        let p = ray.origin + ray.dir * hit.t;
        if material.kind == MATERIAL_EMISSIVE {
            var w = 1.0;
            if bsdf_pdf > 0.0 {
                w = emission_weight(hit.prim, ray.origin, p, ray.dir, hit.t, bsdf_pdf);
            }
            radiance += throughput * material.color * w;
            break;
        }
        let outward = outward_normal(prim, p);
        let front_face = dot(ray.dir, outward) < 0.0;
        let normal = select(-outward, outward, front_face);
        let u = uniform4(pixel, sample, bounce, PURPOSE_SCATTER, frame.seed);
        let s = scatter(material, ray, p, normal, front_face, u);
        if !s.ok {
            break;
        }
        // Direct light at diffuse hits, when the ray it stands in for is within the depth limit.
        let lights_sampled = NEE && material.kind == MATERIAL_LAMBERTIAN && bounce + 2u <= frame.max_depth;
        bsdf_pdf = 0.0;
        if lights_sampled {
            bsdf_pdf = diffuse_pdf(dot(normal, s.dir));
            let shadow = next_event(p, normal, uniform4(pixel, sample, bounce, PURPOSE_LIGHT, frame.seed));
            if shadow.ok {
                instrument(PASS_MEGAKERNEL_SHADOW);
                rays += 1u;
                if !occluded(shadow.ray, T_MIN, shadow.t_max, shadow.light) {
                    radiance += throughput * s.attenuation * shadow.weight;
                }
            }
        }
        throughput *= s.attenuation;
        ray = Ray(p, s.dir);
    }
    *path = TracedPath(ray, throughput, radiance, rays, bsdf_pdf);
}
