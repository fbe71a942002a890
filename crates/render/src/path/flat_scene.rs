//! The path tracer's flat scene: every planar-faceted object baked into world-space
//! triangles under ONE bounding volume hierarchy, so that the Cornell box and scenes
//! like it are traced without a top-level hierarchy, instance transforms or per-shape
//! virtual calls.
//!
//! At setup every object whose shape reports
//! [`Shape::facets_exact`](irradia_geometry::Shape::facets_exact) (polygons, boxes,
//! convex polyhedra: planar, convex faces that *are* the surface) has its faces
//! fan-triangulated and carried to world space by its instance transform. Each
//! triangle keeps its object, material and geometric normal (the shape's own face
//! normal by Newell's method, carried by the inverse transpose, so hits see the same
//! normal the shape would report). The triangles are grouped in eight-triangle SIMD
//! packets ([`TrianglePacket`]). Up to 64 triangles form at most eight packets,
//! grouped as the SAH builder's leaves and culled by one 8-wide test of their boxes
//! ([`PacketBounds`]); more are indexed by the geometry crate's 8-wide SAH hierarchy
//! (Wald, Benthin, Boulos, "Getting Rid of Packets", RT 2008) with packet leaves,
//! except the few triangles whose boxes are a large part of the scene's (the walls of a
//! room around a mesh, a ground plane: [`LARGE_TRIANGLE_AREA`]), which every ray tests
//! first, as a small scene's, and whose nearest hit bounds the walk of the tree.
//!
//! Triangle meshes ([`Shape::as_triangle_mesh`](irradia_geometry::Shape::as_triangle_mesh)) are baked
//! too, triangle by triangle, each with the geometric normal the mesh's hit reports
//! and its three vertex normals carried to world space ([`SmoothNormals`]): a hit
//! interpolates them into the shading normal with the mesh's own rules (Phong shading
//! normals; given normals turn the geometric normal to their side, as in pbrt).
//!
//! Everything else (spheres, quadrics, tori, CSG, implicit surfaces, textured objects whose
//! `uv` matters) stays in an [`Accel`] of the other instances; the nearer hit wins.
//!
//! The geometry is the same surface, so the image is statistically the same; hits differ
//! from the shapes' own tests only by rounding (f32 world-space triangles instead of the
//! polygons' f64 plane test or the mesh's watertight object-space test). Surface
//! coordinates `uv` of baked hits are the triangle's barycentrics (not a mesh's texture
//! coordinates), which is why objects with textured materials are not baked.

mod baked;
mod packet_nearest;

use baked::Baked;

use super::material_map::{desc_anisotropic, desc_uniform};
use super::tracer::{SubsetAccel, Tracer};
use glam::{DVec3, Vec2, Vec3};
use irradia_core::{Ray, Rgb};
use irradia_geometry::mesh::TriangleMesh;
use irradia_geometry::packet::has_avx2;
use irradia_geometry::packet::lanes::{Fw, Mw, V3, W};
use irradia_geometry::packet::ray_lanes::LaneHits;
use irradia_geometry::packet::{PacketHit, RayLaneTriangles};
use irradia_geometry::triangle::TriangleHit;
use irradia_geometry::{Accel, Hit, Instance, ObjectSet, RayQuery, RaySegment, SceneHit};
use irradia_scene::{Scene, Texture};

/// One baked world-space triangle.
#[derive(Clone, Copy, Debug)]
struct FlatTriangle {
    corners: [Vec3; 3],
    /// Unit geometric normal, the shape's face normal in world space.
    normal: Vec3,
    instance: u32,
    material: u32,
    /// The face of the shape's facets the triangle belongs to (reported as `Hit::prim`).
    face: u32,
    /// A mesh triangle's vertex normals (smooth shading); `None` for flat faces.
    smooth: Option<SmoothNormals>,
}

/// A baked triangle as the wide kernel reads it: corners, unit normal, instance,
/// material, vertex normals of a mesh triangle.
pub(crate) type BakedTriangle = ([Vec3; 3], Vec3, u32, u32, Option<SmoothNormals>);

/// The vertex normals of a baked mesh triangle, for smooth shading as
/// [`TriangleMesh`]'s own hits do it (Phong's interpolated normals, the shading normal of
/// pbrt's and Mitsuba's triangle meshes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SmoothNormals {
    /// The mesh's unit vertex normals carried to world space by the inverse transpose
    /// and *not* renormalised: the transform is linear, so their barycentric blend,
    /// normalised, points where the mesh's blend (normalised in object space, carried,
    /// normalised again) does, up to rounding.
    pub normals: [Vec3; 3],
    /// [`TriangleMesh::normals_given`]: given normals turn the geometric normal to
    /// their side, computed ones are turned to the geometric normal's side.
    pub given: bool,
}

impl SmoothNormals {
    /// The geometric and shading normals at barycentrics `(b1, b2)` of the triangle
    /// whose unit geometric normal is `n`: the blend of the vertex normals, normalised,
    /// oriented by the mesh's own rules
    /// ([`oriented_normals`](irradia_geometry::mesh::oriented_normals)), in world space.
    #[inline(always)]
    pub fn at(&self, n: Vec3, b1: f32, b2: f32) -> (Vec3, Vec3) {
        let b0 = 1.0 - b1 - b2;
        let [n0, n1, n2] = self.normals;
        let ns = (b0 * n0 + b1 * n1 + b2 * n2).normalize_or_zero();
        irradia_geometry::mesh::oriented_normals(n, ns, self.given)
    }
}

/// A face of an object as baked: world-space corners, unit normal, the face's index in
/// the shape, vertex normals (meshes).
struct BakedFace {
    corners: [Vec3; 3],
    normal: Vec3,
    face: u32,
    smooth: Option<SmoothNormals>,
}

/// The world-space triangles of a mesh placed by `instance`, each with its geometric
/// normal as the mesh's hit reports it (`(p1 - p0) x (p2 - p0)` normalised in object
/// space, carried by the inverse transpose and normalised, unless the transform is the
/// identity) and its vertex normals. Degenerate triangles, which the mesh never hits,
/// are left out. `None` when a normal is not finite (the mesh keeps its own test).
fn bake_mesh(instance: &Instance, mesh: &TriangleMesh) -> Option<Vec<BakedFace>> {
    let to_world = *instance.to_world();
    let identity = to_world == glam::Affine3A::IDENTITY;
    let normal_to_world = instance.to_object().matrix3.transpose();
    let carry = |n: Vec3| Vec3::from(normal_to_world * glam::Vec3A::from(n));
    let (positions, normals) = (mesh.positions(), mesh.normals());
    let given = mesh.normals_given();
    let mut out = Vec::with_capacity(mesh.triangle_count());
    for (face, t) in mesh.indices().iter().enumerate() {
        let [i0, i1, i2] = t.map(|i| i as usize);
        let (p0, p1, p2) = (positions[i0], positions[i1], positions[i2]);
        let cross = (p1 - p0).cross(p2 - p0);
        if cross == Vec3::ZERO {
            continue;
        }
        let normal = if identity {
            cross.normalize()
        } else {
            carry(cross.normalize()).normalize()
        };
        if !normal.is_finite() {
            return None;
        }
        let (corners, vertex_normals) = if identity {
            ([p0, p1, p2], [normals[i0], normals[i1], normals[i2]])
        } else {
            (
                [p0, p1, p2].map(|p| to_world.transform_point3(p)),
                [normals[i0], normals[i1], normals[i2]].map(carry),
            )
        };
        out.push(BakedFace {
            corners,
            normal,
            face: face as u32,
            smooth: Some(SmoothNormals {
                normals: vertex_normals,
                given,
            }),
        });
    }
    Some(out)
}

/// The scene as the path tracer traces it: baked triangles plus the remaining shapes.
#[derive(Debug)]
pub struct FlatScene {
    baked: Option<Baked>,
    rest: Option<SubsetAccel>,
    baked_objects: usize,
    /// Per scene object: its material and its CSG leaves' materials.
    materials: Vec<(u32, Vec<u32>)>,
    /// Per scene object: whether its shape is a closed solid.
    solid: Vec<bool>,
    /// The baked triangles for answering W rays at once, when the whole scene is
    /// baked into at most [`MAX_TRIANGLES`](irradia_geometry::packet::ray_lanes::MAX_TRIANGLES).
    ray_lanes: Option<RayLaneTriangles>,
}

/// The world-space triangles of `instance` (triangle meshes with their vertex normals,
/// shapes whose facets are exact fan-triangulated), or `None` when it cannot be baked
/// exactly.
fn bake_instance(instance: &Instance) -> Option<Vec<BakedFace>> {
    let shape = instance.shape.as_ref();
    if let Some(mesh) = shape.as_triangle_mesh() {
        return bake_mesh(instance, mesh);
    }
    if !shape.facets_exact() {
        return None;
    }
    let facets = shape.facets(64)?;
    if !facets.normals.is_empty() {
        return None; // smooth shading normals: leave to the shape
    }
    let to_world = instance.to_world();
    let normal_to_world = instance.to_object().matrix3.transpose();
    let mut out = Vec::new();
    for (face_index, face) in facets.faces.iter().enumerate() {
        let v: Vec<DVec3> = face
            .iter()
            .map(|&i| facets.vertices.get(i as usize).map(|p| p.as_dvec3()))
            .collect::<Option<_>>()?;
        if v.len() < 3 {
            return None;
        }
        // Newell's normal around the centroid, as the polygon computes its own.
        let centroid = v.iter().sum::<DVec3>() / v.len() as f64;
        let newell = (0..v.len()).fold(DVec3::ZERO, |acc, i| {
            acc + (v[i] - centroid).cross(v[(i + 1) % v.len()] - centroid)
        });
        if newell.length_squared() == 0.0 {
            return None;
        }
        let n_obj = newell.normalize();
        // A fan from the first vertex covers the face exactly when every fan triangle
        // turns the same way as the face (convex faces always do).
        for k in 1..v.len() - 1 {
            if (v[k] - v[0]).cross(v[k + 1] - v[0]).dot(n_obj) <= 0.0 {
                return None;
            }
        }
        let normal = Vec3::from(normal_to_world * glam::Vec3A::from(n_obj.as_vec3())).normalize();
        if !normal.is_finite() {
            return None;
        }
        let world = |p: DVec3| to_world.transform_point3(p.as_vec3());
        for k in 1..v.len() - 1 {
            out.push(BakedFace {
                corners: [world(v[0]), world(v[k]), world(v[k + 1])],
                normal,
                face: face_index as u32,
                smooth: None,
            });
        }
    }
    Some(out)
}

/// Asks the CPU to start loading the cache lines of the first `bytes` of `*p` (a hint:
/// no effect on the result, never a fault).
#[inline(always)]
pub(crate) fn prefetch_bytes<T>(p: &T, bytes: usize) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let p = p as *const T as *const i8;
        let bytes = bytes.min(std::mem::size_of::<T>()).max(1);
        let mut at = 0;
        while at < bytes {
            // SAFETY: a prefetch is only a hint; the address is inside `*p`.
            unsafe { _mm_prefetch(p.add(at), _MM_HINT_T0) };
            at += 64;
        }
        // The last byte's line, when `p` is not aligned to a line.
        // SAFETY: as above.
        unsafe { _mm_prefetch(p.add(bytes - 1), _MM_HINT_T0) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (p, bytes);
}

impl FlatScene {
    /// Bakes every object of `scene` that can be baked exactly; the others go to a
    /// smaller [`Accel`].
    pub fn new(scene: &Scene) -> Self {
        let mut triangles = Vec::new();
        let mut rest = Vec::new();
        let mut rest_index = Vec::new();
        let mut baked_objects = 0;
        for (i, (object, instance)) in scene
            .objects
            .iter()
            .zip(scene.accel.instances())
            .enumerate()
        {
            let material = object.material;
            // Baked hits carry barycentric uv and no tangent frame: only objects whose
            // material reads neither (no image on a lecture material, no texture and
            // no anisotropy in a physically based description, no textured emission)
            // are baked.
            let plain = object.leaf_materials.is_empty()
                && scene.materials.get(material as usize).is_some_and(|m| {
                    !matches!(m.color, Texture::Image { .. })
                        && m.emission_texture.is_none()
                        && m.bsdf
                            .as_deref()
                            .is_none_or(|d| desc_uniform(d) && !desc_anisotropic(d))
                });
            match plain.then(|| bake_instance(instance)).flatten() {
                Some(tris) => {
                    baked_objects += 1;
                    triangles.extend(tris.into_iter().map(|f| FlatTriangle {
                        corners: f.corners,
                        normal: f.normal,
                        instance: i as u32,
                        material,
                        face: f.face,
                        smooth: f.smooth,
                    }))
                }
                None => {
                    rest.push(instance.clone());
                    rest_index.push(i as u32);
                }
            }
        }
        let emissive: Vec<bool> = scene
            .materials
            .iter()
            .map(|m| m.emission != Rgb::BLACK || m.emission_texture.is_some())
            .collect();
        let mut flat = Self {
            baked: (!triangles.is_empty()).then(|| Baked::build(triangles, &emissive)),
            rest: (!rest.is_empty()).then(|| SubsetAccel {
                accel: Accel::build(rest),
                scene_index: rest_index,
            }),
            baked_objects,
            materials: scene
                .objects
                .iter()
                .map(|o| (o.material, o.leaf_materials.clone()))
                .collect(),
            solid: scene
                .accel
                .instances()
                .iter()
                .map(|i| i.shape.is_solid())
                .collect(),
            ray_lanes: None,
        };
        flat.ray_lanes = flat.all_triangles().and_then(|t| {
            let corners: Vec<[Vec3; 3]> = t.iter().map(|t| t.0).collect();
            RayLaneTriangles::new(&corners, &flat.packet_order())
        });
        flat
    }

    /// How many objects were baked into triangles.
    pub fn baked_objects(&self) -> usize {
        self.baked_objects
    }

    /// How many world-space triangles were baked.
    pub fn triangle_count(&self) -> usize {
        self.baked.as_ref().map_or(0, |b| b.triangles.len())
    }

    /// Shape of the triangle hierarchy (`None` when nothing was baked).
    pub fn bvh_stats(&self) -> Option<irradia_geometry::bvh::BvhStats> {
        self.baked
            .as_ref()
            .and_then(|b| b.bvh.as_ref())
            .map(|b| b.stats())
    }

    /// Every baked triangle as (corners, unit normal, instance, material, vertex
    /// normals) when the whole scene is baked (no shape is left to its own test), for
    /// the wide kernel ([`super::wide`]); `None` otherwise.
    pub(crate) fn all_triangles(&self) -> Option<Vec<BakedTriangle>> {
        if self.rest.is_some() {
            return None;
        }
        self.baked_triangles()
    }

    /// Every baked triangle as [`Self::all_triangles`] lists them, whether or not some
    /// shapes are left to their own tests; `None` when nothing was baked.
    pub(crate) fn baked_triangles(&self) -> Option<Vec<BakedTriangle>> {
        let baked = self.baked.as_ref()?;
        Some(
            baked
                .triangles
                .iter()
                .map(|t| (t.corners, t.normal, t.instance, t.material, t.smooth))
                .collect(),
        )
    }

    /// The geometric and shading normals of baked triangle `tri` at barycentrics
    /// `(b1, b2)`, as its hits report them.
    #[inline]
    pub(crate) fn hit_normals(&self, tri: u32, b1: f32, b2: f32) -> Option<(Vec3, Vec3)> {
        let t = self.baked.as_ref()?.triangles.get(tri as usize)?;
        Some(match &t.smooth {
            Some(s) => s.at(t.normal, b1, b2),
            None => (t.normal, t.normal),
        })
    }

    /// The baked triangles in the order the packets hold them (the order in which a
    /// ray tests them), as indices of [`Self::all_triangles`].
    pub(crate) fn packet_order(&self) -> Vec<u32> {
        self.baked
            .as_ref()
            .map_or(Vec::new(), |b| b.triangles_in(0..b.packets.len()))
    }

    /// The nearest baked triangle along each of `rays` (at most `W`, the path kernel's
    /// lanes; `t > 0`, unbounded), into `out`: its index (as in [`Self::all_triangles`]) and the hit,
    /// as the single ray's `closest_hit` finds it; the rays walk the BVH in turns.
    pub(crate) fn nearest_triangles(&self, rays: &[Ray], out: &mut [Option<(u32, PacketHit)>]) {
        assert!(rays.len() <= W && out.len() == rays.len());
        match &self.baked {
            Some(b) => b.intersect_many(rays, out),
            None => out.fill(None),
        }
    }

    /// The triangles every ray tests before the hierarchy, in packet order, as indices
    /// of [`Self::all_triangles`], when the scene has a hierarchy (a large scene's large
    /// triangles); empty otherwise.
    pub(crate) fn first_order(&self) -> Vec<u32> {
        match &self.baked {
            Some(b) if b.bvh.is_some() => b.triangles_in(0..b.first),
            _ => Vec::new(),
        }
    }

    /// The nearest triangle of the hierarchy alone (not the [first](Self::first_order)
    /// ones) along each of `rays` (at most `W`), ray `i` with `0 < t < t_max[i]`, into
    /// `out`, as [`Self::nearest_triangles`] reports them.
    pub(crate) fn nearest_in_tree(
        &self,
        rays: &[Ray],
        t_max: &[f32],
        out: &mut [Option<(u32, PacketHit)>],
    ) {
        assert!(rays.len() <= W && out.len() == rays.len() && t_max.len() == rays.len());
        match &self.baked {
            Some(b) => b.tree_nearest_many(rays, t_max, out),
            None => out.fill(None),
        }
    }

    /// Whether a triangle of the hierarchy alone is hit with `0 < t < t_max[i]` by each
    /// of `rays` (at most `W`), into `out`.
    pub(crate) fn occluded_in_tree(&self, rays: &[Ray], t_max: &[f32], out: &mut [bool]) {
        assert!(rays.len() <= W && out.len() == rays.len() && t_max.len() == rays.len());
        match &self.baked {
            Some(b) => b.tree_any_many(rays, t_max, out),
            None => out.fill(false),
        }
    }

    /// Whether a baked triangle is hit with `0 < t < t_max[i]` by each of `rays`,
    /// into `out`; the rays walk the BVH in turns.
    pub(crate) fn occluded_baked_many(&self, rays: &[Ray], t_max: &[f32], out: &mut [bool]) {
        assert!(rays.len() <= W && out.len() == rays.len() && t_max.len() == rays.len());
        match &self.baked {
            Some(b) => b.occluded_many(rays, t_max, out),
            None => out.fill(false),
        }
    }

    /// The scene indices of the objects left to their own shapes' tests (none when
    /// every object is baked).
    pub(crate) fn rest_objects(&self) -> &[u32] {
        self.rest.as_ref().map_or(&[], |r| &r.scene_index)
    }

    /// How many objects are intersected through their own shapes.
    pub fn generic_objects(&self) -> usize {
        self.rest.as_ref().map_or(0, |r| r.scene_index.len())
    }
}

impl FlatScene {
    /// The world-space hit of baked triangle `tri` at `t` with barycentrics `b1, b2`.
    #[inline(always)]
    fn baked_hit(baked: &Baked, tri: u32, t: f32, b1: f32, b2: f32) -> SceneHit {
        let tri = &baked.triangles[tri as usize];
        let [p0, p1, p2] = tri.corners;
        let (point, error) = TriangleHit {
            t,
            b0: 1.0 - b1 - b2,
            b1,
            b2,
        }
        .point_and_error(p0, p1, p2);
        let (normal, shading_normal) = match &tri.smooth {
            Some(s) => s.at(tri.normal, b1, b2),
            None => (tri.normal, tri.normal),
        };
        SceneHit {
            instance: tri.instance,
            hit: Hit {
                t,
                point,
                normal,
                shading_normal,
                uv: Vec2::new(b1, b2),
                prim: tri.face,
                leaf: 0,
                error,
            },
        }
    }
}

/// Up to W segments in the ray lanes (origins, directions, ends, active lanes).
fn lanes_of(segments: &[RaySegment]) -> (V3, V3, Fw, Mw) {
    let zero = || V3::new(Fw::ZERO, Fw::ZERO, Fw::ZERO);
    let (mut o, mut d, mut t_max, mut active) = (zero(), zero(), Fw::ZERO, Mw::FALSE);
    for (lane, s) in segments.iter().enumerate() {
        (o.x.0[lane], o.y.0[lane], o.z.0[lane]) = s.ray.origin.into();
        (d.x.0[lane], d.y.0[lane], d.z.0[lane]) = s.ray.dir.into();
        t_max.0[lane] = s.t_max;
        active.0[lane] = -1;
    }
    (o, d, t_max, active)
}

impl RayQuery for FlatScene {
    /// Every object counts as opaque (see [`ObjectSet`]): the path tracer asks about
    /// [`ObjectSet::All`] only.
    #[inline]
    fn closest_hit(&self, set: ObjectSet, ray: &Ray, t_max: f32) -> Option<SceneHit> {
        if set == ObjectSet::Clear {
            return None;
        }
        let mut best = None;
        let mut t_max = t_max;
        if let Some(baked) = &self.baked {
            if let Some((tri, h)) = baked.intersect(ray, t_max) {
                t_max = h.t;
                best = Some(Self::baked_hit(baked, tri, h.t, h.b1, h.b2));
            }
        }
        if let Some(rest) = &self.rest {
            if let Some(h) = rest.intersect(ray, t_max) {
                best = Some(h);
            }
        }
        best
    }

    #[inline]
    fn any_hit(&self, set: ObjectSet, ray: &Ray, t_max: f32) -> bool {
        set != ObjectSet::Clear
            && (self.baked.as_ref().is_some_and(|b| b.occluded(ray, t_max))
                || self
                    .rest
                    .as_ref()
                    .is_some_and(|r| r.accel.occluded(ray, t_max)))
    }

    #[inline]
    fn is_solid(&self, object: u32) -> bool {
        self.solid[object as usize]
    }

    /// Small fully baked scenes: W rays against every triangle in one pass
    /// ([`RayLaneTriangles`]), with the single-ray form's arithmetic and tie order.
    fn closest_hits(&self, set: ObjectSet, segments: &[RaySegment], out: &mut [Option<SceneHit>]) {
        assert_eq!(segments.len(), out.len(), "one answer per segment");
        let (Some(lanes), Some(baked), false) =
            (&self.ray_lanes, &self.baked, set == ObjectSet::Clear)
        else {
            for (s, o) in segments.iter().zip(out.iter_mut()) {
                *o = self.closest_hit(set, &s.ray, s.t_max);
            }
            return;
        };
        for (segs, outs) in segments.chunks(W).zip(out.chunks_mut(W)) {
            let (o, d, t_max, active) = lanes_of(segs);
            let h = ray_lanes_nearest(lanes, o, d, t_max, active);
            for (lane, slot) in outs.iter_mut().enumerate() {
                *slot = h.hit.get(lane).then(|| {
                    let (t, b1, b2) = (h.t.0[lane], h.b1.0[lane], h.b2.0[lane]);
                    Self::baked_hit(baked, h.triangle[lane], t, b1, b2)
                });
            }
        }
    }

    fn any_hits(&self, set: ObjectSet, segments: &[RaySegment], out: &mut [bool]) {
        assert_eq!(segments.len(), out.len(), "one answer per segment");
        let (Some(lanes), false) = (&self.ray_lanes, set == ObjectSet::Clear) else {
            for (s, o) in segments.iter().zip(out.iter_mut()) {
                *o = self.any_hit(set, &s.ray, s.t_max);
            }
            return;
        };
        for (segs, outs) in segments.chunks(W).zip(out.chunks_mut(W)) {
            let (o, d, t_max, active) = lanes_of(segs);
            let hit = ray_lanes_occluded(lanes, o, d, t_max, active);
            for (lane, slot) in outs.iter_mut().enumerate() {
                *slot = hit.get(lane);
            }
        }
    }
}

/// The ray-lane kernel with the arithmetic of the packet test the single-ray form
/// runs: fused (AVX2 + FMA) when the CPU has it, unfused (SSE) otherwise.
fn ray_lanes_nearest(lanes: &RayLaneTriangles, o: V3, d: V3, t_max: Fw, active: Mw) -> LaneHits {
    #[cfg(target_arch = "x86_64")]
    if has_avx2() {
        #[target_feature(enable = "avx2,fma")]
        unsafe fn fused(l: &RayLaneTriangles, o: V3, d: V3, t: Fw, a: Mw) -> LaneHits {
            l.nearest_within::<true>(o, d, t, a)
        }
        // SAFETY: the CPU supports AVX2 and FMA.
        return unsafe { fused(lanes, o, d, t_max, active) };
    }
    lanes.nearest_within::<false>(o, d, t_max, active)
}

/// As [`ray_lanes_nearest`], for shadow rays.
fn ray_lanes_occluded(lanes: &RayLaneTriangles, o: V3, d: V3, t_max: Fw, active: Mw) -> Mw {
    #[cfg(target_arch = "x86_64")]
    if has_avx2() {
        #[target_feature(enable = "avx2,fma")]
        unsafe fn fused(l: &RayLaneTriangles, o: V3, d: V3, t: Fw, a: Mw) -> Mw {
            l.occluded::<true>(o, d, t, a)
        }
        // SAFETY: the CPU supports AVX2 and FMA.
        return unsafe { fused(lanes, o, d, t_max, active) };
    }
    lanes.occluded::<false>(o, d, t_max, active)
}

impl Tracer for FlatScene {
    #[inline]
    fn material(&self, object: u32, leaf: u32) -> u32 {
        let (material, leaves) = &self.materials[object as usize];
        leaves.get(leaf as usize).copied().unwrap_or(*material)
    }
}
