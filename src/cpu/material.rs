//! Scattering by the book's materials; twin of `shaders/shared/material.wgsl`.

use super::texture::{self, TexturePoint};
use super::{ray::Ray, real::Real, sampling::unit_vector, vec3::V3};
use crate::layout::{material_kind, MaterialRecord};
use crate::numerics::Fresnel;

/// Where a path goes next and how much of it survives.
#[derive(Clone, Copy, Debug)]
pub struct Scatter<T> {
    pub attenuation: V3<T>,
    pub dir: V3<T>,
}

#[inline(always)]
pub fn reflect<T: Real>(v: V3<T>, n: V3<T>) -> V3<T> {
    v - n * (T::of(2.0) * v.dot(n))
}

#[inline(always)]
pub fn refract<T: Real>(uv: V3<T>, n: V3<T>, eta_ratio: T) -> V3<T> {
    let cos_theta = (-uv).dot(n).min(T::one());
    let perp = (uv + n * cos_theta) * eta_ratio;
    let parallel = n * -(T::one() - perp.length_squared()).abs().sqrt();
    perp + parallel
}

/// Schlick's approximation of Fresnel reflectance.
#[inline(always)]
pub fn reflectance<T: Real>(cosine: T, eta_ratio: T) -> T {
    let r0 = (T::one() - eta_ratio) / (T::one() + eta_ratio);
    let r0 = r0 * r0;
    r0 + (T::one() - r0) * (T::one() - cosine).powi(5)
}

/// The exact unpolarised Fresnel reflectance of a dielectric boundary for incident cosine
/// `cos_i` and `eta_ratio` = n_incident / n_transmitted: the mean of the squared s- and
/// p-polarised amplitude ratios (Hecht, Optics §4.6), 1 under total internal reflection.
#[inline(always)]
pub fn fresnel_exact<T: Real>(cos_i: T, eta_ratio: T) -> T {
    let sin2_t = eta_ratio * eta_ratio * (T::one() - cos_i * cos_i).max(T::zero());
    if sin2_t >= T::one() {
        return T::one();
    }
    let cos_t = (T::one() - sin2_t).sqrt();
    let parallel = (cos_i - eta_ratio * cos_t) / (cos_i + eta_ratio * cos_t);
    let perpendicular = (eta_ratio * cos_i - cos_t) / (eta_ratio * cos_i + cos_t);
    (parallel * parallel + perpendicular * perpendicular) / T::of(2.0)
}

/// The chance a ray at incident cosine `cos` reflects off glass, as `fresnel` computes it.
#[inline(always)]
pub fn reflect_probability<T: Real>(cos: T, eta_ratio: T, fresnel: Fresnel) -> T {
    match fresnel {
        Fresnel::Schlick => reflectance(cos, eta_ratio),
        Fresnel::Exact => fresnel_exact(cos, eta_ratio),
    }
}

/// Scatters `ray` at the surface point whose texture is looked up at `at` with shading normal
/// `normal` (facing the ray), `front_face` true when the ray arrived from outside. `u` are the
/// bounce's three scatter numbers; glass reflects by `fresnel`. `None`: the path is absorbed
/// (or the surface only emits).
#[inline(always)]
pub fn scatter<T: Real>(
    m: &MaterialRecord,
    ray: &Ray<T>,
    at: &TexturePoint<T>,
    normal: V3<T>,
    front_face: bool,
    u: [f32; 4],
    fresnel: Fresnel,
) -> Option<Scatter<T>> {
    match m.kind {
        material_kind::LAMBERTIAN => {
            let d = normal + unit_vector(u[0], u[1]);
            // The book's near_zero guard: a sample opposite the normal falls back to it.
            let tiny = T::of(1e-8);
            let dir = if d.x.abs() < tiny && d.y.abs() < tiny && d.z.abs() < tiny { normal } else { d };
            Some(Scatter { attenuation: texture::albedo(m, at), dir: dir.normalize() })
        }
        material_kind::METAL => {
            let fuzz = T::of(m.param);
            let dir = reflect(ray.dir, normal) + unit_vector::<T>(u[0], u[1]) * fuzz;
            if dir.dot(normal) <= T::zero() {
                return None;
            }
            Some(Scatter { attenuation: texture::albedo(m, at), dir: dir.normalize() })
        }
        material_kind::DIELECTRIC => {
            let ior = T::of(m.param);
            let ri = if front_face { T::one() / ior } else { ior };
            let cos_theta = (-ray.dir).dot(normal).min(T::one());
            let sin_theta = (T::one() - cos_theta * cos_theta).max(T::zero()).sqrt();
            let cannot_refract = ri * sin_theta > T::one();
            let dir = if cannot_refract || reflect_probability(cos_theta, ri, fresnel) > T::of(u[2]) {
                reflect(ray.dir, normal)
            } else {
                refract(ray.dir, normal, ri)
            };
            Some(Scatter { attenuation: V3::splat(T::one()), dir: dir.normalize() })
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(kind: u32, color: [f32; 3], param: f32) -> MaterialRecord {
        MaterialRecord { color, param, kind, ..Default::default() }
    }

    fn ray(d: [f64; 3]) -> Ray<f64> {
        Ray { origin: V3::splat(0.0), dir: V3::new(d[0], d[1], d[2]).normalize() }
    }

    #[test]
    fn total_internal_reflection_inside_glass() {
        // Leaving glass (ior 1.5) at 60° from the normal: sin 60° · 1.5 > 1, so every sample
        // reflects back inside whatever the random choice.
        let glass = record(material_kind::DIELECTRIC, [1.0; 3], 1.5);
        let n = V3::new(0.0, -1.0, 0.0); // facing the ray, which travels up and out
        let r = ray([60f64.to_radians().sin(), 60f64.to_radians().cos(), 0.0]);
        for u in [0.0, 0.5, 0.999] {
            let s = scatter(
                &glass,
                &r,
                &TexturePoint::at(V3::splat(0.0)),
                n,
                false,
                [0.3, 0.3, u, 0.0],
                Fresnel::Schlick,
            )
            .unwrap();
            assert!(s.dir.y < 0.0, "reflected back down into the glass");
            assert!((s.dir.y + r.dir.y).abs() < 1e-12 && (s.dir.x - r.dir.x).abs() < 1e-12);
        }
    }

    #[test]
    fn refraction_obeys_snell_entering_glass() {
        let glass = record(material_kind::DIELECTRIC, [1.0; 3], 1.5);
        let n = V3::new(0.0, 1.0, 0.0);
        let r = ray([30f64.to_radians().sin(), -30f64.to_radians().cos(), 0.0]);
        // u = 0.999 > Schlick reflectance (~0.04): refracts.
        let s = scatter(
            &glass,
            &r,
            &TexturePoint::at(V3::splat(0.0)),
            n,
            true,
            [0.0, 0.0, 0.999, 0.0],
            Fresnel::Schlick,
        )
        .unwrap();
        let sin_out = s.dir.x / s.dir.length();
        assert!((sin_out - 0.5 / 1.5).abs() < 1e-12, "sin θt = sin θi / 1.5");
        assert!(s.dir.y < 0.0);
        // u = 0 < reflectance: reflects.
        let s = scatter(
            &glass,
            &r,
            &TexturePoint::at(V3::splat(0.0)),
            n,
            true,
            [0.0, 0.0, 0.0, 0.0],
            Fresnel::Schlick,
        )
        .unwrap();
        assert!(s.dir.y > 0.0);
    }

    #[test]
    fn schlick_matches_fresnel_at_normal_incidence() {
        assert!((reflectance(1.0f64, 1.0 / 1.5) - 0.04).abs() < 1e-12);
        assert!((reflectance(0.0f64, 1.0 / 1.5) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn lambertian_goes_into_the_upper_hemisphere_with_albedo() {
        let m = record(material_kind::LAMBERTIAN, [0.2, 0.4, 0.6], 0.0);
        let n = V3::new(0.0, 0.0, 1.0);
        let mut st = crate::rng::Stream::new(5);
        for _ in 0..1000 {
            let u = [st.next_f32(), st.next_f32(), 0.0, 0.0];
            let s = scatter(
                &m,
                &ray([0.0, 0.0, -1.0]),
                &TexturePoint::at(V3::splat(0.0)),
                n,
                true,
                u,
                Fresnel::Schlick,
            )
            .unwrap();
            assert!(s.dir.dot(n) >= 0.0);
            assert!((s.dir.length() - 1.0).abs() < 1e-12);
            assert_eq!(s.attenuation, V3::new(0.2f32 as f64, 0.4f32 as f64, 0.6f32 as f64));
        }
    }

    #[test]
    fn perfect_metal_mirrors_and_fuzzy_metal_absorbs_below_the_surface() {
        let mirror = record(material_kind::METAL, [1.0; 3], 0.0);
        let n = V3::new(0.0, 1.0, 0.0);
        let r = ray([1.0, -1.0, 0.0]);
        let s = scatter(
            &mirror,
            &r,
            &TexturePoint::at(V3::splat(0.0)),
            n,
            true,
            [0.1, 0.2, 0.0, 0.0],
            Fresnel::Schlick,
        )
        .unwrap();
        assert!((s.dir.x - r.dir.x).abs() < 1e-12 && (s.dir.y + r.dir.y).abs() < 1e-12);
        // A grazing ray with full fuzz: some samples end below the surface and are absorbed.
        let fuzzy = record(material_kind::METAL, [1.0; 3], 1.0);
        let grazing = ray([1.0, -0.01, 0.0]);
        let mut st = crate::rng::Stream::new(6);
        let absorbed = (0..1000)
            .filter(|_| {
                scatter(
                    &fuzzy,
                    &grazing,
                    &TexturePoint::at(V3::splat(0.0)),
                    n,
                    true,
                    [st.next_f32(), st.next_f32(), 0.0, 0.0],
                    Fresnel::Schlick,
                )
                .is_none()
            })
            .count();
        assert!(absorbed > 100 && absorbed < 900, "{absorbed}");
    }

    #[test]
    fn exact_fresnel_matches_the_textbook_values() {
        // Air to glass (1.5) at normal incidence: ((1 − 1.5)/(1 + 1.5))² = 4%.
        assert!((fresnel_exact(1.0f64, 1.0 / 1.5) - 0.04).abs() < 1e-12);
        // Leaving glass at 40°: 24.5% exact, where Schlick (in the incident cosine) says 4.1%.
        let c = 40f64.to_radians().cos();
        assert!((fresnel_exact(c, 1.5) - 0.245).abs() < 5e-4, "{}", fresnel_exact(c, 1.5));
        assert!((reflectance(c, 1.5) - 0.041).abs() < 5e-4);
        // Beyond the critical angle (41.8°): total internal reflection.
        assert_eq!(fresnel_exact(42f64.to_radians().cos(), 1.5), 1.0);
        // Grazing incidence from air reflects everything; both terms agree there.
        assert!((fresnel_exact(0.0f64, 1.0 / 1.5) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn emitters_do_not_scatter() {
        let light = record(material_kind::EMISSIVE, [4.0; 3], 0.0);
        assert!(scatter(
            &light,
            &ray([0.0, 0.0, 1.0]),
            &TexturePoint::at(V3::splat(0.0)),
            V3::new(0.0, 0.0, -1.0),
            true,
            [0.5; 4],
            Fresnel::Schlick
        )
        .is_none());
    }
}
