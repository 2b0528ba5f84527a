//! The packed .fmu as users receive it: layout, self-containment, GUID agreement.

use crate::common;
use common::*;

#[test]
fn the_archive_has_the_standard_layout_and_no_build_tree_path() {
    let fmu = torsional();
    for entry in [
        "modelDescription.xml",
        "binaries/linux64/torsional.so",
        "documentation/index.html",
        "resources",
    ] {
        assert!(fmu.dir.join(entry).exists(), "{entry} missing");
    }
    assert!(!fmu.dir.join("binaries/linux64/libtorsional.so").exists());
    let tree = env!("CARGO_MANIFEST_DIR").as_bytes();
    for file in [
        "modelDescription.xml",
        "binaries/linux64/torsional.so",
        "documentation/index.html",
    ] {
        let bytes = std::fs::read(fmu.dir.join(file)).unwrap();
        assert!(
            !bytes.windows(tree.len()).any(|w| w == tree),
            "{file} contains the build-tree path"
        );
    }
}

#[test]
fn the_packed_xml_carries_the_binary_guid_and_documents_every_variable() {
    let fmu = torsional();
    assert!(fmu.description.guid.starts_with('{') && fmu.description.guid.len() == 38);
    assert_eq!(fmu.description.guid, windrive::models::torsional::GUID);
    // instantiation checks the GUID against the one compiled into the binary
    fmu.instantiate("guid", false).unwrap();
    let doc = std::fs::read_to_string(fmu.dir.join("documentation/index.html")).unwrap();
    for v in &fmu.description.model_variables.variables {
        assert!(
            doc.contains(&format!("<code>{}</code>", v.name)),
            "{} undocumented",
            v.name
        );
    }
    assert!(doc.contains("Stiction"), "the brake model is explained");
}
