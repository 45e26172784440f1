//! Wavefront OBJ, the subset a triangle mesh needs: `v x y z` vertices, `vt u v` texture
//! coordinates and `f` faces (`f 1 2 3`, `f 1/1/1 ...`, `f 1//1 ...`, negative indices counting
//! back from the last vertex or texture coordinate). Polygons with more than three corners are
//! split into a fan. The mesh has texture coordinates when every face corner names one that is
//! defined (otherwise it has none, and [`ObjMesh::uv_note`] says why); OBJ's v runs up the
//! image, ours (glTF's) down, so `vt u v` is stored as (u, 1 − v). Everything else
//! (normals, groups, materials) is ignored: wavetrace shades with the scene's material and the
//! geometric normal.
//!
//! Hand-written rather than a crate so that every error names the line and the reason.

use glam::{Vec2, Vec3};
use std::path::Path;

/// The mesh's triangles, and how many zero-area ones were dropped.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjMesh {
    pub triangles: Vec<[Vec3; 3]>,
    /// Each triangle's corners' texture coordinates, when every face corner has one.
    pub uvs: Option<Vec<[Vec2; 3]>>,
    /// Why a mesh whose faces name texture coordinates has none: the first line that lacks one
    /// or names one not defined (older files were read without them, so this is no error).
    pub uv_note: Option<String>,
    pub degenerate: usize,
}

/// Reads an OBJ file. The error is `(reason)` without the file name, which the caller adds.
pub fn read(path: &Path) -> Result<ObjMesh, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    parse(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// Parses OBJ text; errors name the 1-based line.
pub fn parse(text: &str) -> Result<ObjMesh, String> {
    let mut vertices: Vec<Vec3> = Vec::new();
    let mut coords: Vec<Vec2> = Vec::new();
    let mut mesh = ObjMesh { triangles: Vec::new(), uvs: None, uv_note: None, degenerate: 0 };
    let mut uvs: Vec<[Vec2; 3]> = Vec::new();
    // Whether some corner names a texture coordinate, and whether every corner so far named a
    // defined one.
    let (mut named, mut complete) = (false, true);
    for (n, line) in text.lines().enumerate() {
        let line_no = n + 1;
        let err = |reason: String| format!("line {line_no}: {reason}");
        let line = line.split('#').next().unwrap_or("");
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let mut p = [0.0f32; 3];
                for (i, c) in p.iter_mut().enumerate() {
                    let w =
                        words.next().ok_or_else(|| err(format!("vertex has {i} coordinates, needs 3")))?;
                    let x: f32 =
                        w.parse().map_err(|_| err(format!("vertex coordinate {w:?} is not a number")))?;
                    if !x.is_finite() {
                        return Err(err(format!("vertex coordinate {w:?} is not finite")));
                    }
                    *c = x;
                }
                // An optional fourth (w) coordinate is allowed by the format and ignored.
                vertices.push(Vec3::from_array(p));
            }
            Some("vt") => {
                let mut uv = [0.0f32; 2];
                for (i, c) in uv.iter_mut().enumerate() {
                    let w = words
                        .next()
                        .ok_or_else(|| err(format!("texture coordinate has {i} numbers, needs 2")))?;
                    let x: f32 =
                        w.parse().map_err(|_| err(format!("texture coordinate {w:?} is not a number")))?;
                    if !x.is_finite() {
                        return Err(err(format!("texture coordinate {w:?} is not finite")));
                    }
                    *c = x;
                }
                coords.push(Vec2::new(uv[0], 1.0 - uv[1]));
            }
            Some("f") => {
                let corners = words
                    .map(|w| corner_indices(w, vertices.len(), coords.len()).map_err(&err))
                    .collect::<Result<Vec<(usize, Option<Option<usize>>)>, String>>()?;
                if corners.len() < 3 {
                    return Err(err(format!("face has {} corners, needs at least 3", corners.len())));
                }
                named |= corners.iter().any(|c| c.1.is_some());
                if complete {
                    if let Some((k, _)) =
                        corners.iter().enumerate().find(|(_, c)| !matches!(c.1, Some(Some(_))))
                    {
                        complete = false;
                        mesh.uv_note = Some(err(format!(
                            "face corner {} names no defined texture coordinate, so the mesh has none",
                            k + 1
                        )));
                    }
                }
                let uv = |k: usize| corners[k].1.flatten().map_or(Vec2::ZERO, |i| coords[i]);
                for i in 1..corners.len() - 1 {
                    let t = [vertices[corners[0].0], vertices[corners[i].0], vertices[corners[i + 1].0]];
                    // Zero-area triangles (common in scanned meshes) have no surface to hit.
                    if (t[1] - t[0]).cross(t[2] - t[0]).length_squared() > 0.0 {
                        mesh.triangles.push(t);
                        uvs.push([uv(0), uv(i), uv(i + 1)]);
                    } else {
                        mesh.degenerate += 1;
                    }
                }
            }
            _ => {}
        }
    }
    if !named {
        mesh.uv_note = None;
    } else if complete {
        mesh.uvs = Some(uvs);
    }
    if mesh.triangles.is_empty() {
        return Err(if mesh.degenerate > 0 {
            format!("all {} triangles have zero area", mesh.degenerate)
        } else {
            "no faces (an OBJ mesh needs `f` lines)".into()
        });
    }
    Ok(mesh)
}

/// The 0-based vertex and texture coordinate of a face corner `v`, `v/vt`, `v//vn` or
/// `v/vt/vn` (1-based, or negative counting back from the latest one): the coordinate `None`
/// when the corner names none, `Some(None)` when it names one not defined.
fn corner_indices(
    word: &str,
    vertices: usize,
    coords: usize,
) -> Result<(usize, Option<Option<usize>>), String> {
    let mut parts = word.split('/');
    let v = parts.next().unwrap_or("");
    let i: i64 = v.parse().map_err(|_| format!("face corner {word:?} does not start with a vertex index"))?;
    let vertex = resolve(i, vertices).ok_or_else(|| {
        format!("face corner {word:?} refers to vertex {i}, but {vertices} vertices are defined before it")
    })?;
    let coord = match parts.next().filter(|t| !t.is_empty()) {
        None => None,
        Some(t) => {
            let j: i64 = t.parse().map_err(|_| {
                format!("face corner {word:?}: texture coordinate index {t:?} is not a number")
            })?;
            Some(resolve(j, coords))
        }
    };
    Ok((vertex, coord))
}

/// A 1-based or negative OBJ index into `defined` items, 0-based.
fn resolve(i: i64, defined: usize) -> Option<usize> {
    let index = if i > 0 { i - 1 } else { defined as i64 + i };
    (i != 0 && index >= 0 && index < defined as i64).then_some(index as usize)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangles_quads_and_index_forms() {
        let m = parse(
            "# a unit square and a triangle\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
             vn 0 0 1\nf 1//1 2//1 3//1 4//1\nf -4/1/1 -3 -1\ng ignored\n",
        )
        .unwrap();
        assert_eq!(m.triangles.len(), 3, "a quad fans into two, plus one");
        assert_eq!(m.triangles[0], [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0)]);
        assert_eq!(m.triangles[2], [Vec3::ZERO, Vec3::X, Vec3::Y]);
        assert_eq!(m.degenerate, 0);
    }

    #[test]
    fn bad_input_names_the_line() {
        let cases = [
            ("v 0 0\n", "line 1: vertex has 2 coordinates"),
            ("v 0 0 x\n", "line 1: vertex coordinate \"x\" is not a number"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "line 4: face corner \"4\" refers to vertex 4, but 3"),
            ("v 0 0 0\nf 1 0 1\n", "line 2: face corner \"0\""),
            ("v 0 0 0\nv 1 0 0\nf 1 2\n", "line 3: face has 2 corners"),
            ("", "no faces"),
            ("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", "all 1 triangles have zero area"),
        ];
        for (text, want) in cases {
            let e = parse(text).unwrap_err();
            assert!(e.contains(want), "{text:?}: {e}");
        }
    }

    #[test]
    fn texture_coordinates_follow_their_corners_with_v_flipped() {
        let m = parse(
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 0.25\nf 1/1 2/2 3/3 4/-1\n",
        )
        .unwrap();
        let uvs = m.uvs.unwrap();
        assert_eq!(uvs.len(), 2);
        assert_eq!(uvs[1], [Vec2::new(0.0, 1.0), Vec2::new(1.0, 0.0), Vec2::new(0.0, 0.75)]);
        let plain = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        assert_eq!((plain.uvs, plain.uv_note), (None, None));
        // Incomplete coordinates: none, and a note naming the line.
        for (text, want) in [
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n", "line 5: face corner 2 names no defined"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2 3/1\n", "line 5: face corner 2"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\nf 1 2 3\n", "line 6: face corner 1"),
        ] {
            let m = parse(text).unwrap();
            assert_eq!(m.uvs, None, "{text:?}");
            assert!(m.uv_note.as_deref().is_some_and(|n| n.contains(want)), "{text:?}: {:?}", m.uv_note);
        }
        for (text, want) in [
            ("vt 0 x\n", "line 1: texture coordinate \"x\" is not a number"),
            ("vt 0\n", "line 1: texture coordinate has 1 numbers"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/x 2 3\n", "texture coordinate index \"x\" is not a number"),
        ] {
            let e = parse(text).unwrap_err();
            assert!(e.contains(want), "{text:?}: {e}");
        }
    }

    #[test]
    fn degenerate_triangles_are_dropped_and_counted() {
        let m = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n").unwrap();
        assert_eq!((m.triangles.len(), m.degenerate), (1, 1));
    }
}
