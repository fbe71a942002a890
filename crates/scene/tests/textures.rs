//! Texture lookups against values computed by hand and by Mitsuba 3.9.1 (scalar_rgb):
//! bitmap filtering, wrapping, sRGB decoding and `to_uv`; the checkerboard's cells;
//! mesh attributes.

use glam::{Affine2, Vec2};
use irradia_core::Rgb;
use irradia_scene::texture::bitmap::read_texels;
use irradia_scene::texture::{
    Bitmap, Checkerboard, FilterType, MeshAttribute, TextureMap, TextureQuery, UvTransform,
    WrapMode,
};
use std::path::PathBuf;
use std::sync::Arc;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/textures")
        .join(name)
}

/// The 4 x 2 test image: rows (top first) red green blue grey128 / yellow cyan magenta
/// (64, 32, 16), 8-bit sRGB.
fn bitmap(filter_type: FilterType, wrap_mode: WrapMode, raw: bool) -> Bitmap {
    Bitmap {
        filename: data("rgb4x2.png"),
        texels: read_texels(&data("rgb4x2.png"), raw).unwrap(),
        filter_type,
        wrap_mode,
        raw,
        to_uv: UvTransform::default(),
    }
}

fn close(got: Rgb, want: [f32; 3], what: &str) {
    for k in 0..3 {
        assert!(
            (got[k] - want[k]).abs() < 2e-5,
            "{what}: got {got:?}, want {want:?}"
        );
    }
}

const UVS: [(f32, f32); 7] = [
    (0.1, 0.2),
    (0.375, 0.25),
    (0.5, 0.5),
    (0.9, 0.9),
    (1.3, -0.2),
    (-0.6, 1.7),
    (0.0, 0.0),
];

/// `mi.load_dict({'type': 'bitmap', 'filename': 'rgb4x2.png', 'filter_type': ..,
/// 'wrap_mode': .., 'raw': ..}).eval(si)` at each of [`UVS`].
#[rustfmt::skip]
const MITSUBA: [(FilterType, WrapMode, bool, [[f32; 3]; 7]); 8] = [
    (FilterType::Nearest, WrapMode::Repeat, false, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 1.0], [0.051269, 0.014444, 0.005182], [0.0, 1.0, 1.0], [0.0, 1.0, 1.0], [1.0, 0.0, 0.0]]),
    (FilterType::Nearest, WrapMode::Mirror, true, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 1.0], [0.25098, 0.12549, 0.062745], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]),
    (FilterType::Nearest, WrapMode::Clamp, false, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 1.0], [0.051269, 0.014444, 0.005182], [0.21586, 0.21586, 0.21586], [1.0, 1.0, 0.0], [1.0, 0.0, 0.0]]),
    (FilterType::Bilinear, WrapMode::Repeat, false, [[0.91994, 0.109572, 0.019479], [0.0, 1.0, 0.0], [0.25, 0.5, 0.75], [0.190582, 0.137382, 0.061547], [0.3, 0.97, 0.63], [0.09, 0.9, 0.91], [0.566782, 0.307576, 0.05526]]),
    (FilterType::Bilinear, WrapMode::Repeat, true, [[0.947686, 0.136431, 0.045804], [0.0, 1.0, 0.0], [0.25, 0.5, 0.75], [0.393647, 0.284588, 0.175059], [0.3, 0.97, 0.63], [0.09, 0.9, 0.91], [0.688235, 0.406863, 0.141176]]),
    (FilterType::Bilinear, WrapMode::Mirror, false, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.25, 0.5, 0.75], [0.051269, 0.014444, 0.005182], [0.064758, 0.064758, 0.764758], [0.09, 0.1, 0.91], [1.0, 0.0, 0.0]]),
    (FilterType::Bilinear, WrapMode::Mirror, true, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.25, 0.5, 0.75], [0.25098, 0.12549, 0.062745], [0.150588, 0.150588, 0.850588], [0.09, 0.1, 0.91], [1.0, 0.0, 0.0]]),
    (FilterType::Bilinear, WrapMode::Clamp, true, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.25, 0.5, 0.75], [0.25098, 0.12549, 0.062745], [0.501961, 0.501961, 0.501961], [1.0, 1.0, 0.0], [1.0, 0.0, 0.0]]),
];

#[test]
fn bitmap_lookups_match_mitsuba() {
    for (filter, wrap, raw, want) in MITSUBA {
        let b = bitmap(filter, wrap, raw);
        for (uv, w) in UVS.iter().zip(want) {
            close(
                b.eval(Vec2::new(uv.0, uv.1)),
                w,
                &format!("{filter:?} {wrap:?} raw={raw} at {uv:?}"),
            );
        }
    }
}

#[test]
fn bitmap_lookups_by_hand() {
    // uv (0, 0) is the top-left corner; v runs down the file.
    let b = bitmap(FilterType::Nearest, WrapMode::Repeat, true);
    close(b.eval(Vec2::new(0.01, 0.01)), [1.0, 0.0, 0.0], "top left");
    close(
        b.eval(Vec2::new(0.01, 0.99)),
        [1.0, 1.0, 0.0],
        "bottom left",
    );
    close(
        b.eval(Vec2::new(0.99, 0.99)),
        [64.0 / 255.0, 32.0 / 255.0, 16.0 / 255.0],
        "bottom right",
    );
    // sRGB decoding of 128: ((128/255 + 0.055) / 1.055)^2.4.
    let grey = ((128.0f32 / 255.0 + 0.055) / 1.055).powf(2.4);
    let lin = bitmap(FilterType::Nearest, WrapMode::Repeat, false);
    close(lin.eval(Vec2::new(0.8, 0.2)), [grey; 3], "decoded grey");
    // Bilinear halfway between the centres of red (0, 0) and green (1, 0), raw.
    let bl = bitmap(FilterType::Bilinear, WrapMode::Clamp, true);
    close(
        bl.eval(Vec2::new(0.25, 0.25)),
        [0.5, 0.5, 0.0],
        "red-green midpoint",
    );
    // A texel centre returns the texel exactly.
    close(
        bl.eval(Vec2::new(0.625, 0.75)),
        [1.0, 0.0, 1.0],
        "magenta centre",
    );
}

#[test]
fn to_uv_scales_then_translates_like_mitsuba() {
    // Mitsuba: to_uv = translate([0.25, 0]) @ scale([2, 1]) at uv (0.1, 0.3) gives
    // [0.03, 0.7, 0.37] and eval_1 (luminance) 0.5336947.
    let mut b = bitmap(FilterType::Bilinear, WrapMode::Repeat, false);
    b.to_uv = UvTransform(
        Affine2::from_translation(Vec2::new(0.25, 0.0)) * Affine2::from_scale(Vec2::new(2.0, 1.0)),
    );
    close(b.eval(Vec2::new(0.1, 0.3)), [0.03, 0.7, 0.37], "to_uv");
    let map = TextureMap::Bitmap(Arc::new(b));
    let q = TextureQuery::at_uv(Vec2::new(0.1, 0.3));
    assert!(
        (map.eval_1(&q) - 0.533_694_7).abs() < 2e-5,
        "{}",
        map.eval_1(&q)
    );
}

#[test]
fn checkerboard_cells_as_mitsuba() {
    // Mitsuba 3.9.1, color0 = 1, color1 = 0: `eval_1` at these uvs gave 0 1 1 0 0 1 0 1,
    // and `eval` (a colour) the opposite cells (white at (0.25, 0.25) and (0, 0)).
    let c = Checkerboard {
        color0: Rgb::WHITE,
        color1: Rgb::BLACK,
        to_uv: UvTransform::default(),
    };
    let cases = [
        ((0.25, 0.25), 0.0),
        ((0.75, 0.25), 1.0),
        ((0.25, 0.75), 1.0),
        ((0.75, 0.75), 0.0),
        ((0.5, 0.5), 0.0),
        ((0.5, 0.75), 1.0),
        ((1.25, 0.25), 0.0),
        ((-0.25, 0.25), 1.0),
    ];
    for ((u, v), want) in cases {
        assert_eq!(
            c.eval_1_color(Vec2::new(u, v)).r,
            want,
            "eval_1 at ({u}, {v})"
        );
        assert_eq!(c.eval(Vec2::new(u, v)).r, 1.0 - want, "eval at ({u}, {v})");
    }
    assert_eq!(c.eval(Vec2::ZERO).r, 1.0);
    let scaled = Checkerboard {
        to_uv: UvTransform(Affine2::from_scale(Vec2::splat(2.0))),
        ..c
    };
    assert_eq!(scaled.eval_1_color(Vec2::new(0.3, 0.1)).r, 1.0);
    assert_eq!(scaled.eval(Vec2::new(0.3, 0.1)).r, 0.0);
    assert_eq!(Checkerboard::default().color0, Rgb::splat(0.4));
}

/// A unit square of two triangles, (0,0)-(1,0)-(0,1) and (1,0)-(1,1)-(0,1), with a
/// colour per vertex, a weight and a colour per face.
fn attributed_square() -> irradia_geometry::TriangleMesh {
    use glam::Vec3;
    use irradia_geometry::mesh::{MeshAttribute as Attr, MeshAttributes};
    let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)];
    let mut attrs = MeshAttributes::default();
    let vertex = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.2, 0.4, 0.6];
    attrs
        .insert(Attr::new("vertex_color", 3, vertex.to_vec()).unwrap())
        .unwrap();
    attrs
        .insert(Attr::new("face_weight", 1, vec![0.25, 0.75]).unwrap())
        .unwrap();
    let face = vec![0.1, 0.2, 0.3, 0.5, 0.5, 0.5];
    attrs
        .insert(Attr::new("face_color", 3, face).unwrap())
        .unwrap();
    irradia_geometry::TriangleMesh::new(positions, vec![[0, 1, 2], [1, 3, 2]], None, None)
        .unwrap()
        .with_attributes(attrs)
        .unwrap()
}

/// Mitsuba's `mesh_attribute` against values worked out by hand: a face attribute is
/// the triangle's row wherever it is hit; a vertex attribute is the corners' rows
/// blended with the point's barycentric coordinates.
#[test]
fn mesh_attributes_are_looked_up_at_the_hit() {
    use glam::Vec3;
    let mesh = attributed_square();
    let tex = |name: &str, scale: f32| {
        TextureMap::MeshAttribute(MeshAttribute {
            name: name.into(),
            scale,
        })
    };
    let query = |p: Vec3, tri: u32| TextureQuery {
        uv: Vec2::ZERO,
        attributes: mesh.attribute_point(p, tri),
    };
    // (0.2, 0.3) on the first triangle: barycentrics (0.5, 0.2, 0.3).
    let q = query(Vec3::new(0.2, 0.3, 0.0), 0);
    close(
        tex("vertex_color", 1.0).eval(&q),
        [0.5, 0.2, 0.3],
        "vertex colour",
    );
    close(
        tex("vertex_color", 2.0).eval(&q),
        [1.0, 0.4, 0.6],
        "× scale",
    );
    close(
        tex("face_color", 1.0).eval(&q),
        [0.1, 0.2, 0.3],
        "face colour",
    );
    assert!((tex("face_weight", 1.0).eval_1(&q) - 0.25).abs() < 1e-6);
    // (0.8, 0.7) on the second: corners 1, 3, 2 with barycentrics (0.3, 0.5, 0.2),
    // so 0.3 (0, 1, 0) + 0.5 (0.2, 0.4, 0.6) + 0.2 (0, 0, 1).
    let q = query(Vec3::new(0.8, 0.7, 0.0), 1);
    close(
        tex("vertex_color", 1.0).eval(&q),
        [0.1, 0.5, 0.5],
        "vertex colour",
    );
    close(
        tex("face_weight", 1.0).eval(&q),
        [0.75; 3],
        "one channel as a colour: grey",
    );
    assert!((tex("face_weight", 2.0).eval_1(&q) - 1.5).abs() < 1e-6);
    assert_eq!(
        tex("face_color", 1.0).eval_1(&q),
        0.0,
        "three channels as a number"
    );
    close(
        tex("vertex_colour", 1.0).eval(&q),
        [0.0; 3],
        "no such attribute",
    );
    close(
        tex("vertex_color", 1.0).eval(&TextureQuery::default()),
        [0.0; 3],
        "no mesh",
    );
}

/// The lookup through a placed instance: the world-space hit is carried back to the
/// mesh's own space before its barycentrics are taken.
#[test]
fn mesh_attributes_through_an_instance_transform() {
    use glam::{Affine3A, Vec3};
    let mesh: Arc<dyn irradia_geometry::Shape> = Arc::new(attributed_square());
    let to_world = Affine3A::from_translation(Vec3::new(5.0, -2.0, 1.0))
        * Affine3A::from_scale(Vec3::splat(2.0));
    let inst = irradia_geometry::Instance::new(mesh, to_world);
    // Object point (0.2, 0.3, 0) is world (5.4, -1.4, 1).
    let ray = irradia_core::Ray::new(Vec3::new(5.4, -1.4, 3.0), Vec3::new(0.0, 0.0, -1.0));
    let hit = inst
        .intersect(&ray, f32::INFINITY)
        .expect("the square is hit");
    let q = TextureQuery {
        uv: hit.uv,
        attributes: inst.attribute_point(&hit),
    };
    let v = TextureMap::MeshAttribute(MeshAttribute {
        name: "vertex_color".into(),
        scale: 1.0,
    });
    close(
        v.eval(&q),
        [0.5, 0.2, 0.3],
        "vertex colour at the world hit",
    );
}

#[test]
fn corrupt_and_missing_files_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.png");
    std::fs::write(&bad, b"\x89PNG\r\n\x1a\nnot really").unwrap();
    let e = read_texels(&bad, false).unwrap_err();
    assert!(e.contains("cannot decode"), "{e}");
    let e = read_texels(&dir.path().join("none.png"), false).unwrap_err();
    assert!(e.contains("cannot open"), "{e}");
}

/// EXR and HDR are linear whatever `raw` says; JPEG is sRGB unless `raw` (Mitsuba
/// 3.9.1, nearest lookups at texel centres of files it wrote itself; the HDR file's
/// signature was changed from Mitsuba's `#?RGBE` to `#?RADIANCE`, the only one the
/// `image` crate reads).
#[test]
fn file_formats_decode_as_mitsuba_decides() {
    // (file, raw, lookup uvs, expected colours, tolerance)
    type Case = (&'static str, bool, [(f32, f32); 2], [[f32; 3]; 2], f32);
    let cases: [Case; 6] = [
        (
            "float2x1.exr",
            false,
            [(0.25, 0.5), (0.75, 0.5)],
            [[0.25, 0.5, 2.0], [0.75, 0.125, 0.0]],
            1e-6,
        ),
        (
            "float2x1.exr",
            true,
            [(0.25, 0.5), (0.75, 0.5)],
            [[0.25, 0.5, 2.0], [0.75, 0.125, 0.0]],
            1e-6,
        ),
        (
            "float2x1.hdr",
            false,
            [(0.25, 0.5), (0.75, 0.5)],
            [[0.25, 0.5, 2.0], [0.75, 0.125, 0.0]],
            1e-6,
        ),
        (
            "float2x1.hdr",
            true,
            [(0.25, 0.5), (0.75, 0.5)],
            [[0.25, 0.5, 2.0], [0.75, 0.125, 0.0]],
            1e-6,
        ),
        (
            "grey8x8.jpg",
            false,
            [(0.0625, 0.0625), (0.9375, 0.9375)],
            [[0.21586; 3], [0.577581; 3]],
            0.005,
        ),
        (
            "grey8x8.jpg",
            true,
            [(0.0625, 0.0625), (0.9375, 0.9375)],
            [[0.501961; 3], [0.784314; 3]],
            0.005,
        ),
    ];
    for (name, raw, uvs, want, tol) in cases {
        let texels = read_texels(&data(name), raw).unwrap_or_else(|e| panic!("{e}"));
        let b = Bitmap {
            filename: data(name),
            texels,
            filter_type: FilterType::Nearest,
            wrap_mode: WrapMode::Repeat,
            raw,
            to_uv: UvTransform::default(),
        };
        for (uv, w) in uvs.iter().zip(want) {
            let got = b.eval(Vec2::new(uv.0, uv.1));
            for k in 0..3 {
                assert!(
                    (got[k] - w[k]).abs() <= tol,
                    "{name} raw={raw} at {uv:?}: {got:?} vs {w:?}"
                );
            }
        }
    }
}

/// BMP files (Mitsuba's test scenes use them) decode as 8-bit sRGB, as Mitsuba reads
/// them: `rgb4x2.bmp` holds the PNG's pixels, and pip Mitsuba 3.9.1's `bitmap` of it
/// (nearest) gives (0.0512694, 0.0144439, 0.00518151) at uv (0.9, 0.9) and red at
/// (0.1, 0.2).
#[test]
fn bmp_reads_as_the_same_srgb_texels() {
    let bmp = read_texels(&data("rgb4x2.bmp"), false).unwrap();
    let png = read_texels(&data("rgb4x2.png"), false).unwrap();
    assert_eq!(bmp, png);
    let b = Bitmap {
        filename: data("rgb4x2.bmp"),
        texels: bmp,
        filter_type: FilterType::Nearest,
        wrap_mode: WrapMode::Repeat,
        raw: false,
        to_uv: UvTransform::default(),
    };
    close(
        b.eval(Vec2::new(0.9, 0.9)),
        [0.0512694, 0.0144439, 0.00518151],
        "bmp at (0.9, 0.9)",
    );
    close(
        b.eval(Vec2::new(0.1, 0.2)),
        [1.0, 0.0, 0.0],
        "bmp at (0.1, 0.2)",
    );
}

/// A material's `emission` may be a texture table: read at the surface's uv by the
/// path tracer, its mean standing for the constant elsewhere.
#[test]
fn emission_texture_is_read_with_its_mean() {
    let text = r#"
[camera]
eye = [0, 1, 5]
look_at = [0, 0, 0]

[materials.screen]
type = "diffuse"
emission = { type = "checkerboard", color0 = 5, color1 = 1 }

[materials.lamp]
emission = { type = "checkerboard", color0 = [1, 2, 3], color1 = 0 }
"#;
    let s = irradia_scene::load_str(
        text,
        irradia_scene::SceneSyntax::Toml,
        std::path::Path::new("t.toml"),
    )
    .unwrap();
    let screen = &s.materials[0];
    assert_eq!(screen.emission, Rgb::splat(3.0));
    assert!(matches!(
        screen.emission_texture,
        Some(TextureMap::Checkerboard(_))
    ));
    assert_eq!(screen.emission_at(Vec2::new(0.25, 0.25)), Rgb::splat(5.0));
    assert_eq!(screen.emission_at(Vec2::new(0.75, 0.25)), Rgb::splat(1.0));
    let lamp = &s.materials[1];
    assert_eq!(lamp.emission, Rgb::new(0.5, 1.0, 1.5));
    assert!(lamp.emission_texture.is_some());
}
