//! The end of a run of pbrt directives: the graphics state's materials, lights, object
//! groups and objects written as Irradia's tree, with notes on blocks left open.

use super::Builder;
use crate::pbrt::coverage::Coverage;
use crate::Imported;
use irradia_scene::file::tree::{line_col, Node, Value};
use std::collections::HashSet;

impl Builder {
    /// What was read, per directive and type.
    pub fn coverage(&self) -> Coverage {
        self.cov.clone()
    }

    /// The tree.
    pub fn finish(mut self, text: String) -> Imported {
        if self.mirror.is_none() {
            self.mirror();
        }
        if !self.stack.is_empty() {
            let (_, kind, pos) = self.stack[self.stack.len() - 1];
            // The main file's stack only: positions are in the main text.
            let (l, c) = line_col(&text, pos);
            self.notes
                .push(format!("{kind} at {l}:{c} is never closed"));
        }
        let mut root = Node::table(0);
        let (camera, image, render) = self.view_nodes();
        root.set("camera", camera);
        root.set("image", image);
        root.set("render", render);
        if !self.mats.is_empty() {
            let mut mats = Node::table(0);
            for (name, node) in std::mem::take(&mut self.mats) {
                mats.set(&name, node);
            }
            root.set("materials", mats);
        }
        if !self.lights.is_empty() {
            root.set("lights", Node::new(std::mem::take(&mut self.lights), 0));
        }
        let used_groups: HashSet<String> = self
            .objects
            .iter()
            .filter_map(|o| match o.get("group").map(|g| &g.value) {
                Some(Value::Str(s)) => Some(s.clone()),
                _ => None,
            })
            .collect();
        let groups: Vec<Node> = std::mem::take(&mut self.groups)
            .into_iter()
            .filter(|(name, objs, _)| !objs.is_empty() && used_groups.contains(name))
            .map(|(name, objs, pos)| {
                let mut g = Node::table(pos);
                g.put("name", name.as_str(), pos);
                g.set("objects", Node::new(objs, pos));
                g
            })
            .collect();
        if !groups.is_empty() {
            root.set("shape_groups", Node::new(groups, 0));
        }
        if !self.objects.is_empty() {
            root.set("objects", Node::new(std::mem::take(&mut self.objects), 0));
        }
        Imported {
            tree: root,
            text,
            origin: self.origin.clone(),
            warnings: self.warnings,
            notes: self.notes,
        }
    }
}
