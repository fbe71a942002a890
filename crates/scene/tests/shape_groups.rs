//! The example of docs/scene-format.md's "Shape groups and instances" loads: two
//! instances of one shared group, whose leaves carry the members' materials.

use irradia_scene::{load_str, SceneSyntax};
use std::path::Path;

#[test]
fn the_documented_example_loads_as_two_instances_of_one_group() {
    let doc = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/scene-format.md"),
    )
    .unwrap();
    let start = doc.find("### Shape groups and instances").expect("section");
    let rest = &doc[start..];
    let block = rest.split("```toml\n").nth(1).expect("example");
    let block = &block[..block.find("```").unwrap()];
    let text = format!(
        "[camera]\neye = [0, 1, 6]\nlook_at = [0, 1, 0]\n\n[materials.bark]\ncolor = [0.4, 0.3, 0.2]\n\
         [materials.leaves]\ncolor = [0.2, 0.6, 0.2]\n\n{block}"
    );
    let scene = load_str(&text, SceneSyntax::Toml, Path::new("doc.toml"))
        .unwrap_or_else(|e| panic!("{e}\n{text}"));
    assert_eq!(scene.objects.len(), 2);
    let shapes = scene.accel.instances();
    assert!(
        std::sync::Arc::ptr_eq(&shapes[0].shape, &shapes[1].shape),
        "one shared group"
    );
    assert_eq!(shapes[0].shape.kind(), "group");
    let names: Vec<&str> = (0..2)
        .map(|leaf| {
            scene.materials[scene.objects[0].material_for_leaf(leaf) as usize]
                .name
                .as_str()
        })
        .collect();
    assert_eq!(names, ["bark", "leaves"]);
}
