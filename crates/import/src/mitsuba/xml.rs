//! Mitsuba 3's XML as elements: the file parsed (roxmltree), its `<default>`s and
//! `-D` values substituted for `$name`, its `<include>`s spliced in and its `<path>`s
//! collected. What comes out is plain elements, each knowing the file and byte offset
//! it came from (for errors) and its place in the main file (for the scene tree).

use irradia_scene::file::tree::line_col;
use irradia_scene::SceneError;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// One XML file's text.
#[derive(Debug)]
pub struct Source {
    pub path: PathBuf,
    pub text: String,
}

impl Source {
    /// An error at byte `pos` of this file.
    pub fn err(&self, pos: usize, field: &str, msg: impl Into<String>) -> SceneError {
        let (line, col) = line_col(&self.text, pos);
        SceneError::input(field, msg)
            .at(line, col)
            .with_file(&self.path)
    }
}

/// An attribute, its value with `$name`s substituted.
#[derive(Debug, Clone)]
pub struct Attr {
    pub name: String,
    pub value: String,
    pub pos: usize,
}

/// An element of a scene file.
#[derive(Debug, Clone)]
pub struct Elem {
    pub tag: String,
    pub attrs: Vec<Attr>,
    pub children: Vec<Elem>,
    pub src: Rc<Source>,
    /// Byte offset of the element in `src`.
    pub pos: usize,
    /// Byte offset in the main file: the element's own, or that of the `<include>`
    /// that brought it in.
    pub main_pos: usize,
}

impl Elem {
    pub fn attr(&self, name: &str) -> Option<&Attr> {
        self.attrs.iter().find(|a| a.name == name)
    }

    pub fn get(&self, name: &str) -> Option<&str> {
        self.attr(name).map(|a| a.value.as_str())
    }

    /// An error at this element.
    pub fn err(&self, field: &str, msg: impl Into<String>) -> SceneError {
        self.src.err(self.pos, field, msg)
    }

    /// An error at attribute `name` (at the element when it is absent).
    pub fn err_at(&self, name: &str, field: &str, msg: impl Into<String>) -> SceneError {
        let pos = self.attr(name).map_or(self.pos, |a| a.pos);
        self.src.err(pos, field, msg)
    }

    /// The attribute `name`, required.
    pub fn req(&self, name: &str) -> Result<&str, SceneError> {
        self.get(name)
            .ok_or_else(|| self.err(name, format!("<{}> needs the attribute `{name}`", self.tag)))
    }

    /// Only these attributes may appear.
    pub fn check_attrs(&self, allowed: &[&str]) -> Result<(), SceneError> {
        for a in &self.attrs {
            if !allowed.contains(&a.name.as_str()) {
                return Err(self.src.err(
                    a.pos,
                    &a.name,
                    format!(
                        "unknown attribute `{}` of <{}> (valid: {})",
                        a.name,
                        self.tag,
                        allowed.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The folder of the file this element is in.
    pub fn dir(&self) -> PathBuf {
        self.src
            .path
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default()
    }
}

/// How deep `<include>`s may nest (a cycle stops here).
const MAX_INCLUDE_DEPTH: usize = 16;

/// Reads scene files: parameters, includes and search paths.
pub struct Loader {
    /// `-D` values (they win over `<default>`s) and the `<default>`s met so far.
    params: HashMap<String, String>,
    /// Folders named by `<path>`, most recent first.
    pub search: Vec<PathBuf>,
    depth: usize,
    /// Files may be read from disk (off for the in-memory fuzz entry point).
    pub read_files: bool,
}

impl Loader {
    pub fn new(defines: &[(String, String)], read_files: bool) -> Loader {
        Loader {
            params: defines.iter().cloned().collect(),
            search: Vec::new(),
            depth: 0,
            read_files,
        }
    }

    /// Parses `src` (a whole file whose root is `<scene>`) into its root element.
    /// `main_pos` is the place in the main file that stands for this file's
    /// elements (`None` for the main file itself).
    pub fn load(&mut self, src: Rc<Source>, main_pos: Option<usize>) -> Result<Elem, SceneError> {
        let opts = roxmltree::ParsingOptions {
            allow_dtd: true,
            nodes_limit: 10_000_000,
        };
        let doc = roxmltree::Document::parse_with_options(&src.text, opts).map_err(|e| {
            let p = e.pos();
            SceneError::input("", format!("XML syntax error: {e}"))
                .at(p.row as usize, p.col as usize)
                .with_file(&src.path)
        })?;
        let root = doc.root_element();
        if root.tag_name().name() != "scene" {
            return Err(src.err(
                root.range().start,
                "",
                format!(
                    "the root element must be <scene>, not <{}>",
                    root.tag_name().name()
                ),
            ));
        }
        let mut elem = self.element(root, &src, main_pos)?;
        // The root's children are read in order: `<default>` before what uses it.
        elem.children = self.children(root, &src, main_pos)?;
        Ok(elem)
    }

    fn element(
        &self,
        node: roxmltree::Node,
        src: &Rc<Source>,
        main_pos: Option<usize>,
    ) -> Result<Elem, SceneError> {
        let pos = node.range().start;
        let mut attrs = Vec::new();
        for a in node.attributes() {
            let value = self.substitute(a.value(), src, a.range_value().start)?;
            attrs.push(Attr {
                name: a.name().to_string(),
                value,
                pos: a.range_value().start,
            });
        }
        Ok(Elem {
            tag: node.tag_name().name().to_string(),
            attrs,
            children: Vec::new(),
            src: src.clone(),
            pos,
            main_pos: main_pos.unwrap_or(pos),
        })
    }

    fn children(
        &mut self,
        node: roxmltree::Node,
        src: &Rc<Source>,
        main_pos: Option<usize>,
    ) -> Result<Vec<Elem>, SceneError> {
        let mut out = Vec::new();
        for child in node.children() {
            if child.is_text() {
                if let Some(t) = child.text() {
                    if !t.trim().is_empty() {
                        return Err(src.err(
                            child.range().start,
                            "",
                            format!("unexpected text `{}`", t.trim()),
                        ));
                    }
                }
                continue;
            }
            if !child.is_element() {
                continue; // comments, processing instructions
            }
            let mut e = self.element(child, src, main_pos)?;
            match e.tag.as_str() {
                "default" => {
                    e.check_attrs(&["name", "value"])?;
                    let name = e.req("name")?.to_string();
                    let value = e.req("value")?.to_string();
                    self.params.entry(name).or_insert(value);
                }
                "path" => {
                    e.check_attrs(&["value"])?;
                    let dir = e.dir().join(e.req("value")?);
                    self.search.insert(0, dir);
                }
                "include" => {
                    e.check_attrs(&["filename"])?;
                    let file = e.req("filename")?;
                    if !self.read_files {
                        return Err(e.err("filename", "<include> is not read from memory"));
                    }
                    let path = self.resolve(&e.dir(), file).ok_or_else(|| {
                        e.err_at("filename", "filename", format!("cannot find `{file}`"))
                    })?;
                    if self.depth >= MAX_INCLUDE_DEPTH {
                        return Err(e.err(
                            "filename",
                            format!("includes nest more than {MAX_INCLUDE_DEPTH} deep (a cycle?)"),
                        ));
                    }
                    let text = crate::read_text(&path)
                        .map_err(|err| e.err_at("filename", "filename", err.to_string()))?;
                    let inc = Rc::new(Source { path, text });
                    self.depth += 1;
                    let root = self.load(inc, Some(main_pos.unwrap_or(e.pos)));
                    self.depth -= 1;
                    out.extend(root?.children);
                }
                _ => {
                    e.children = self.children(child, src, main_pos)?;
                    out.push(e);
                }
            }
        }
        Ok(out)
    }

    /// `$name` replaced by its value; an undefined one is an error.
    fn substitute(&self, value: &str, src: &Source, pos: usize) -> Result<String, SceneError> {
        if !value.contains('$') {
            return Ok(value.to_string());
        }
        let mut out = String::new();
        let mut rest = value;
        while let Some(i) = rest.find('$') {
            out.push_str(&rest[..i]);
            let after = &rest[i + 1..];
            let n = after
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .unwrap_or(after.len());
            let name = &after[..n];
            if name.is_empty() {
                out.push('$');
                rest = after;
                continue;
            }
            match self.params.get(name) {
                Some(v) => out.push_str(v),
                None => {
                    return Err(src.err(
                        pos + i,
                        name,
                        format!("undefined scene parameter `${name}`: give it with -D {name}=VALUE or a <default name=\"{name}\" value=\"...\"/>"),
                    ))
                }
            }
            rest = &after[n..];
        }
        out.push_str(rest);
        Ok(out)
    }

    /// A file named in the scene: as given when absolute, else in the folder of the
    /// file that names it, then in the `<path>` folders.
    pub fn resolve(&self, dir: &Path, name: &str) -> Option<PathBuf> {
        let p = Path::new(name);
        if p.is_absolute() {
            return Some(p.to_path_buf());
        }
        if !self.read_files {
            return Some(dir.join(p));
        }
        std::iter::once(dir.to_path_buf())
            .chain(self.search.iter().cloned())
            .map(|d| d.join(p))
            .find(|c| c.exists())
    }
}
