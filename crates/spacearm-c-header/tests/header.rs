//! The C library's committed header `crates/spacearm-c/include/spacearm.h` equals the one cbindgen
//! generates from that crate's source with its `cbindgen.toml` (cbindgen used as a library: CI
//! needs no extra binary). Run with `SPACEARM_BLESS=1` to rewrite the committed header after
//! changing the ABI.

use std::path::Path;

#[test]
fn committed_header_equals_generated() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../spacearm-c");
    let dir = dir.as_path();
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml")).expect("cbindgen.toml");
    let bindings = cbindgen::Builder::new().with_crate(dir).with_config(config).generate().expect("cbindgen generates the header");
    let mut generated = Vec::new();
    bindings.write(&mut generated);
    let path = dir.join("include/spacearm.h");
    if std::env::var_os("SPACEARM_BLESS").is_some() {
        std::fs::write(&path, &generated).expect("write include/spacearm.h");
    }
    let committed = std::fs::read(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "include/spacearm.h differs from what cbindgen generates; run `SPACEARM_BLESS=1 cargo test -p spacearm-c-header` and commit it"
    );
    // The ABI version in the header is the library's (its `pub const` in src/lib.rs).
    let source = std::fs::read_to_string(dir.join("src/lib.rs")).expect("crates/spacearm-c/src/lib.rs");
    let version = source
        .lines()
        .find_map(|line| line.trim().strip_prefix("pub const SPACEARM_ABI_VERSION: u32 = "))
        .and_then(|rest| rest.strip_suffix(';'))
        .expect("src/lib.rs declares `pub const SPACEARM_ABI_VERSION: u32 = N;`");
    let text = String::from_utf8(generated).unwrap();
    assert!(text.contains(&format!("#define SPACEARM_ABI_VERSION {version}")));
}
