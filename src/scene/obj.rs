//! Wavefront OBJ, the subset a triangle mesh needs: `v x y z` vertices and `f` faces (`f 1 2 3`,
//! `f 1/1/1 ...`, `f 1//1 ...`, negative indices counting back from the last vertex). Polygons
//! with more than three corners are split into a fan. Everything else (normals, texture
//! coordinates, groups, materials) is ignored: wavetrace shades with the scene's material and the
//! geometric normal.
//!
//! Hand-written rather than a crate so that every error names the line and the reason.

use glam::Vec3;
use std::path::Path;

/// The mesh's triangles, and how many zero-area ones were dropped.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjMesh {
    pub triangles: Vec<[Vec3; 3]>,
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
    let mut mesh = ObjMesh { triangles: Vec::new(), degenerate: 0 };
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
            Some("f") => {
                let corners =
                    words
                        .map(|w| vertex_index(w, vertices.len()).map_err(&err))
                        .collect::<Result<Vec<usize>, String>>()?;
                if corners.len() < 3 {
                    return Err(err(format!("face has {} corners, needs at least 3", corners.len())));
                }
                for i in 1..corners.len() - 1 {
                    let t = [vertices[corners[0]], vertices[corners[i]], vertices[corners[i + 1]]];
                    // Zero-area triangles (common in scanned meshes) have no surface to hit.
                    if (t[1] - t[0]).cross(t[2] - t[0]).length_squared() > 0.0 {
                        mesh.triangles.push(t);
                    } else {
                        mesh.degenerate += 1;
                    }
                }
            }
            _ => {}
        }
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

/// The 0-based vertex of a face corner `v`, `v/vt`, `v//vn` or `v/vt/vn` (1-based, or negative
/// counting back from the latest vertex).
fn vertex_index(word: &str, defined: usize) -> Result<usize, String> {
    let v = word.split('/').next().unwrap_or("");
    let i: i64 = v.parse().map_err(|_| format!("face corner {word:?} does not start with a vertex index"))?;
    let index = if i > 0 { i - 1 } else { defined as i64 + i };
    if i == 0 || index < 0 || index >= defined as i64 {
        return Err(format!(
            "face corner {word:?} refers to vertex {i}, but {defined} vertices are defined before it"
        ));
    }
    Ok(index as usize)
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
    fn degenerate_triangles_are_dropped_and_counted() {
        let m = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n").unwrap();
        assert_eq!((m.triangles.len(), m.degenerate), (1, 1));
    }
}
