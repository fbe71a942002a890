//! Whatever the text, loading returns a scene or an error: it never panics. Inputs are
//! random bytes and built-in scenes cut short or with one character changed.

use irradia_scene::{builtin, load_str, SceneSyntax};
use proptest::prelude::*;
use std::path::Path;

fn try_load(text: &str, format: SceneSyntax) {
    let r = std::panic::catch_unwind(|| {
        let _ = load_str(text, format, Path::new("fuzz.toml"));
    });
    assert!(r.is_ok(), "panicked on {text:?}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn random_text_never_panics(s in "\\PC{0,200}") {
        try_load(&s, SceneSyntax::Toml);
        try_load(&s, SceneSyntax::Json);
    }

    #[test]
    fn damaged_builtins_never_panic(cut in 0usize..4000, at in 0usize..4000, c in prop::char::range(' ', '~')) {
        let text = builtin::source("csg").unwrap();
        let cut = cut.min(text.len());
        let cut = (0..=cut).rev().find(|&i| text.is_char_boundary(i)).unwrap();
        try_load(&text[..cut], SceneSyntax::Toml);
        let mut chars: Vec<char> = text.chars().collect();
        let at = at % chars.len();
        chars[at] = c;
        let changed: String = chars.into_iter().collect();
        try_load(&changed, SceneSyntax::Toml);
    }
}
