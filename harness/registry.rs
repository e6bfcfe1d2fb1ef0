//! The kinds of case the catalogue knows and the report sections they contribute, in one
//! place: the only module that imports them. Adding a kind is its folder and one line here
//! (two when it brings a section of its own).

use crate::case_kind::{KindEntry, Registry};
use crate::contact_compare::report::ContactSection;
use crate::crosscheck::report::CrosscheckSection;
use crate::material_point::report::MaterialSection;
use crate::report::beam::section::BeamSection;
use crate::report::penetration::section::PenetrationSection;
use crate::report::section::Section;

/// Every kind, under its key in a case file; a case without any of the keys runs its scene.
/// One line per kind, as a table.
#[rustfmt::skip]
pub static KINDS: Registry = Registry {
    keyed: &[
        KindEntry { key: "material_point", parse: crate::material_point::parse },
        KindEntry { key: "contact_problems", parse: crate::contact_problems::parse },
        KindEntry { key: "crosscheck", parse: crate::crosscheck::parse },
        KindEntry { key: "determinism", parse: crate::determinism::parse },
    ],
    default: crate::scene_case::parse,
};

/// The sections the kinds contribute to the report, in page order.
pub static SECTIONS: &[&dyn Section] = &[
    &ContactSection,
    &MaterialSection,
    &CrosscheckSection,
    &BeamSection,
    &PenetrationSection,
];
