use proptest::prelude::*;

use super::*;

#[test]
fn spans_point_at_values_and_keys() {
    let text = "{\n  \"a\": [1, 2.5],\n  \"b\": {\"c\": null}\n}";
    let root = parse(text).unwrap();
    let (node, key) = root.pointer_target("/a/1").unwrap();
    assert_eq!(&text[node.span.clone()], "2.5");
    assert!(key.is_none());
    let (node, key) = root.pointer_target("/b/c").unwrap();
    assert_eq!(&text[node.span.clone()], "null");
    assert_eq!(&text[key.unwrap()], "\"c\"");
    let idx = LineIndex::new(text);
    assert_eq!(idx.line_col(text, node.span.start), (3, 14));
    assert_eq!(idx.line_text(text, 2), "  \"a\": [1, 2.5],");
}

#[test]
fn errors_are_located() {
    for (text, offset, needle) in [
        ("{\"a\": 1,}", 8, "trailing comma"),
        ("[1, 2", 5, "not closed"),
        ("{\"a\": NaN}", 6, "NaN"),
        ("{\"a\": 1e400}", 6, "out of the range"),
        ("{\"a\": 01}", 7, "leading zeros"),
        ("{a: 1}", 1, "property name"),
        ("[1] x", 4, "after the end"),
        ("\"\\ud800\"", 7, "surrogate"),
    ] {
        let e = parse(text).unwrap_err();
        assert_eq!(e.offset, offset, "{text}: {e:?}");
        assert!(e.message.contains(needle), "{text}: {e:?}");
    }
}

#[test]
fn deep_nesting_is_refused_not_a_stack_overflow() {
    let text = "[".repeat(100_000);
    let e = parse(&text).unwrap_err();
    assert!(e.message.contains("nesting"));
    let ok = format!("{}{}", "[".repeat(MAX_DEPTH), "]".repeat(MAX_DEPTH));
    assert!(parse(&ok).is_ok());
}

#[test]
fn integers_stay_integers() {
    let v = parse("[18446744073709551615, -3, 2.0]").unwrap().to_value();
    assert_eq!(v[0].as_u64(), Some(u64::MAX));
    assert_eq!(v[1].as_i64(), Some(-3));
    assert_eq!(v[2].as_f64(), Some(2.0));
    assert!(v[2].is_f64());
}

#[test]
fn duplicate_keys_are_kept_in_order() {
    let root = parse(r#"{"a": 1, "a": 2}"#).unwrap();
    let NodeKind::Object(members) = &root.kind else {
        panic!()
    };
    assert_eq!(members.len(), 2);
    assert_eq!(root.get("a").unwrap().to_value(), serde_json::json!(2));
}

fn arb_json() -> impl Strategy<Value = serde_json::Value> {
    use serde_json::Value as V;
    let leaf = prop_oneof![
        Just(V::Null),
        any::<bool>().prop_map(V::Bool),
        any::<i64>().prop_map(V::from),
        (-1e300f64..1e300).prop_map(V::from),
        "\\PC{0,12}".prop_map(V::String),
    ];
    leaf.prop_recursive(4, 64, 8, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..6).prop_map(V::Array),
            prop::collection::btree_map("\\PC{0,6}", inner, 0..6).prop_map(|m| V::Object(m.into_iter().collect())),
        ]
    })
}

proptest! {
    /// Whatever serde_json writes, we read back to the same value.
    #[test]
    fn agrees_with_serde_json(v in arb_json()) {
        let text = serde_json::to_string_pretty(&v).unwrap();
        let node = parse(&text).unwrap();
        prop_assert_eq!(node.to_value(), v);
    }

    /// Arbitrary text never panics, and we accept exactly what serde_json accepts
    /// (modulo serde_json's leniency with huge numbers and our BOM tolerance).
    #[test]
    fn never_panics_on_garbage(s in "\\PC{0,64}|[\\[\\]{}\",:0-9eE.+\\- tnufals\\\\]{0,64}") {
        let ours = parse(&s);
        let theirs: Result<serde_json::Value, _> = serde_json::from_str(&s);
        if let Ok(node) = &ours {
            prop_assert_eq!(&node.to_value(), theirs.as_ref().unwrap());
        }
        if theirs.is_ok() && !s.starts_with('\u{feff}') {
            prop_assert!(ours.is_ok(), "serde_json accepted {:?}, we said {:?}", s, ours);
        }
    }

    #[test]
    fn line_col_never_panics(s in "\\PC{0,40}", off in 0usize..100) {
        let idx = LineIndex::new(&s);
        let (line, _col) = idx.line_col(&s, off);
        prop_assert!(line >= 1);
        let _ = idx.line_text(&s, line);
    }
}
