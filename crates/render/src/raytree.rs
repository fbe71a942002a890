//! Ray trees (lecture: "Ray Trees"): the camera ray of one pixel, the reflected and
//! refracted rays it spawns, recursively, and the shadow rays cast at every hit.
//!
//! The integrator is generic over a [`Recorder`]. The renderer passes [`NoRecorder`],
//! whose methods are empty and vanish after inlining; `trace-pixel` passes a
//! [`TreeRecorder`], so the tree is built by exactly the code that renders the image.

use glam::Vec3;
use irradia_core::{Ray, Rgb};
use serde::Serialize;
use std::fmt::Write;

/// What a ray is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum RayKind {
    Camera,
    Reflected,
    Refracted,
    Shadow,
}

impl RayKind {
    pub fn name(self) -> &'static str {
        match self {
            RayKind::Camera => "camera",
            RayKind::Reflected => "reflected",
            RayKind::Refracted => "refracted",
            RayKind::Shadow => "shadow",
        }
    }
}

/// Hooks the integrator calls while it traces. Calls nest: `begin` opens a node that
/// later calls describe, `end` closes it.
pub trait Recorder {
    /// False for recorders that keep nothing, so callers can skip work done only to
    /// describe a ray (finding a shadow ray's blocker).
    const RECORDS: bool = true;
    /// A ray of `kind` at `depth` starts with the path weight (product of the
    /// coefficients from the camera) `weight`.
    fn begin(&mut self, kind: RayKind, depth: u32, ray: &Ray, weight: Rgb);
    /// The open ray hit `object` (its index and name) at `point` with `normal`.
    fn hit(&mut self, object: u32, name: &str, point: Vec3, normal: Vec3);
    /// The local (direct) colour computed at the open ray's hit.
    fn local(&mut self, colour: Rgb);
    /// A shadow ray from the open ray's hit: `transmittance` is the fraction of the
    /// light that arrives (0 = blocked); `blocker` the first object in the way.
    fn shadow(&mut self, ray: &Ray, depth: u32, blocker: Option<Blocker<'_>>, transmittance: Rgb);
    /// A ray that would have been spawned was not traced (`why`: "weight" or "depth").
    fn cut(&mut self, kind: RayKind, depth: u32, weight: Rgb, why: &'static str);
    /// The open ray returns `radiance`.
    fn end(&mut self, radiance: Rgb);
}

/// The first opaque object found in the way of a shadow ray.
#[derive(Clone, Copy, Debug)]
pub struct Blocker<'a> {
    pub object: u32,
    pub name: &'a str,
    pub point: Vec3,
    pub normal: Vec3,
}

/// The recorder of ordinary rendering: records nothing, costs nothing.
pub struct NoRecorder;

impl Recorder for NoRecorder {
    const RECORDS: bool = false;
    #[inline(always)]
    fn begin(&mut self, _: RayKind, _: u32, _: &Ray, _: Rgb) {}
    #[inline(always)]
    fn hit(&mut self, _: u32, _: &str, _: Vec3, _: Vec3) {}
    #[inline(always)]
    fn local(&mut self, _: Rgb) {}
    #[inline(always)]
    fn shadow(&mut self, _: &Ray, _: u32, _: Option<Blocker<'_>>, _: Rgb) {}
    #[inline(always)]
    fn cut(&mut self, _: RayKind, _: u32, _: Rgb, _: &'static str) {}
    #[inline(always)]
    fn end(&mut self, _: Rgb) {}
}

/// The object a ray hit, where, and the normal there.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct NodeHit {
    pub object: u32,
    pub name: String,
    pub point: [f32; 3],
    pub normal: [f32; 3],
}

/// One ray of the tree.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct RayNode {
    pub kind: RayKind,
    pub depth: u32,
    pub origin: [f32; 3],
    pub direction: [f32; 3],
    pub hit: Option<NodeHit>,
    /// Local (Phong) colour at the hit; for a shadow ray, the light's transmittance.
    pub local: [f32; 3],
    /// Path weight from the camera (product of the coefficients along the path).
    pub weight: [f32; 3],
    /// Radiance the ray returns (0 for shadow rays).
    pub radiance: [f32; 3],
    /// What the ray adds to the pixel: `weight * radiance`.
    pub contribution: [f32; 3],
    /// Set when the ray was not traced: "weight" (below min_weight) or "depth".
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cut: Option<&'static str>,
    pub children: Vec<RayNode>,
}

/// Builds the tree of one camera sample.
#[derive(Default)]
pub struct TreeRecorder {
    stack: Vec<RayNode>,
    /// Finished roots (one per camera sample traced).
    pub roots: Vec<RayNode>,
}

fn a(v: Vec3) -> [f32; 3] {
    v.to_array()
}

fn node(kind: RayKind, depth: u32, ray: &Ray, weight: Rgb) -> RayNode {
    RayNode {
        kind,
        depth,
        origin: a(ray.origin),
        direction: a(ray.dir),
        hit: None,
        local: [0.0; 3],
        weight: weight.to_array(),
        radiance: [0.0; 3],
        contribution: [0.0; 3],
        cut: None,
        children: Vec::new(),
    }
}

impl Recorder for TreeRecorder {
    fn begin(&mut self, kind: RayKind, depth: u32, ray: &Ray, weight: Rgb) {
        self.stack.push(node(kind, depth, ray, weight));
    }
    fn hit(&mut self, object: u32, name: &str, point: Vec3, normal: Vec3) {
        if let Some(n) = self.stack.last_mut() {
            n.hit = Some(NodeHit {
                object,
                name: name.to_owned(),
                point: a(point),
                normal: a(normal),
            });
        }
    }
    fn local(&mut self, colour: Rgb) {
        if let Some(n) = self.stack.last_mut() {
            n.local = colour.to_array();
        }
    }
    fn shadow(&mut self, ray: &Ray, depth: u32, blocker: Option<Blocker<'_>>, transmittance: Rgb) {
        let weight = self
            .stack
            .last()
            .map(|n| Rgb::from_array(n.weight))
            .unwrap_or(Rgb::WHITE);
        let mut s = node(RayKind::Shadow, depth, ray, weight);
        s.local = transmittance.to_array();
        s.hit = blocker.map(|b| NodeHit {
            object: b.object,
            name: b.name.to_owned(),
            point: a(b.point),
            normal: a(b.normal),
        });
        if let Some(n) = self.stack.last_mut() {
            n.children.push(s);
        }
    }
    fn cut(&mut self, kind: RayKind, depth: u32, weight: Rgb, why: &'static str) {
        let mut c = node(kind, depth, &Ray::new(Vec3::ZERO, Vec3::ZERO), weight);
        c.cut = Some(why);
        if let Some(n) = self.stack.last_mut() {
            if let Some(h) = &n.hit {
                c.origin = h.point;
            }
            n.children.push(c);
        }
    }
    fn end(&mut self, radiance: Rgb) {
        if let Some(mut n) = self.stack.pop() {
            n.radiance = radiance.to_array();
            n.contribution = (Rgb::from_array(n.weight) * radiance).to_array();
            match self.stack.last_mut() {
                Some(parent) => parent.children.push(n),
                None => self.roots.push(n),
            }
        }
    }
}

fn v3(v: [f32; 3]) -> String {
    format!("({:.4}, {:.4}, {:.4})", v[0], v[1], v[2])
}

impl RayNode {
    /// Number of rays in the tree (this one included).
    pub fn count(&self) -> usize {
        1 + self.children.iter().map(RayNode::count).sum::<usize>()
    }

    /// An indented text rendering, one ray per block.
    pub fn to_text(&self) -> String {
        let mut s = String::new();
        self.text_into(&mut s, 0);
        s
    }

    fn text_into(&self, s: &mut String, indent: usize) {
        let pad = "  ".repeat(indent);
        let _ = write!(s, "{pad}{} ray, depth {}", self.kind.name(), self.depth);
        if let Some(why) = self.cut {
            let _ = writeln!(s, ": not traced (cut by {why}), weight {}", v3(self.weight));
            return;
        }
        let _ = writeln!(s);
        let _ = writeln!(
            s,
            "{pad}  origin {}  direction {}",
            v3(self.origin),
            v3(self.direction)
        );
        match (&self.hit, self.kind) {
            (Some(h), RayKind::Shadow) => {
                let verb = if self.local.iter().all(|&v| v == 0.0) {
                    "blocked by"
                } else {
                    "filtered by (first crossed)"
                };
                let _ = writeln!(s, "{pad}  {verb} #{} '{}'", h.object, h.name);
            }
            (Some(h), _) => {
                let _ = writeln!(
                    s,
                    "{pad}  hit #{} '{}' at {}  normal {}",
                    h.object,
                    h.name,
                    v3(h.point),
                    v3(h.normal)
                );
            }
            (None, RayKind::Shadow) => {
                let _ = writeln!(s, "{pad}  reaches the light");
            }
            (None, _) => {
                let _ = writeln!(s, "{pad}  hits nothing (background)");
            }
        }
        if self.kind == RayKind::Shadow {
            let _ = writeln!(s, "{pad}  light transmitted {}", v3(self.local));
        } else {
            let _ = writeln!(
                s,
                "{pad}  local {}  weight {}  radiance {}  contribution {}",
                v3(self.local),
                v3(self.weight),
                v3(self.radiance),
                v3(self.contribution)
            );
        }
        for c in &self.children {
            c.text_into(s, indent + 1);
        }
    }

    /// Graphviz `dot`: one box per ray, edges labelled by ray kind.
    pub fn to_dot(&self) -> String {
        let mut s =
            String::from("digraph raytree {\n  node [shape=box, fontname=\"monospace\"];\n");
        let mut next = 0usize;
        self.dot_into(&mut s, &mut next, None);
        s.push_str("}\n");
        s
    }

    fn dot_into(&self, s: &mut String, next: &mut usize, parent: Option<usize>) {
        let id = *next;
        *next += 1;
        let what = match (&self.hit, self.cut) {
            (_, Some(why)) => format!("cut by {why}"),
            (Some(h), _) if self.kind == RayKind::Shadow => {
                if self.local.iter().all(|&v| v == 0.0) {
                    format!("blocked by {}", esc(&h.name))
                } else {
                    format!("filtered by {}", esc(&h.name))
                }
            }
            (Some(h), _) => format!("hit {} at {}", esc(&h.name), v3(h.point)),
            (None, _) if self.kind == RayKind::Shadow => "reaches light".into(),
            (None, _) => "background".into(),
        };
        let _ = writeln!(
            s,
            "  n{id} [label=\"{} d{}\\n{}\\nlocal {}\\ncontribution {}\"];",
            self.kind.name(),
            self.depth,
            what,
            v3(self.local),
            v3(self.contribution)
        );
        if let Some(p) = parent {
            let style = if self.kind == RayKind::Shadow {
                ", style=dashed"
            } else {
                ""
            };
            let _ = writeln!(
                s,
                "  n{p} -> n{id} [label=\"{}\"{style}];",
                self.kind.name()
            );
        }
        for c in &self.children {
            c.dot_into(s, next, Some(id));
        }
    }
}

fn esc(s: &str) -> String {
    s.replace('\\', "\\\\").replace('"', "\\\"")
}

/// The document `irradia trace-pixel --format json` prints and the Python binding's
/// `Scene.trace_pixel` returns: the pixel, the sample, its radiance, the number of
/// rays and the tree.
pub fn pixel_document(
    x: u32,
    y: u32,
    sample: u32,
    radiance: irradia_core::Rgb,
    tree: &RayNode,
) -> serde_json::Value {
    serde_json::json!({
        "pixel": [x, y],
        "sample": sample,
        "radiance": radiance.to_array(),
        "rays": tree.count(),
        "tree": tree,
    })
}
