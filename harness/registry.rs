//! The kinds of case the catalogue knows, in one place: the only module that imports them.
//! Adding a kind is its folder and one line here.

use crate::case_kind::{KindEntry, Registry};

/// Every kind, under its key in a case file; a case without any of the keys runs its scene.
pub static KINDS: Registry = Registry {
    keyed: &[
        KindEntry {
            key: "material_point",
            parse: crate::material_point::parse,
        },
        KindEntry {
            key: "contact_problems",
            parse: crate::contact_compare::case::parse,
        },
        KindEntry {
            key: "crosscheck",
            parse: crate::crosscheck::parse,
        },
    ],
    default: crate::scene_case::parse,
};
