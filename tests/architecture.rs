//! The shape of the code: the docking core imports nothing from the shell,
//! and every shader parses.

use std::path::Path;

fn rust_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).expect("read dir").flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn the_core_imports_nothing_from_the_shell() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    for core in ["model", "collide", "motion", "session"] {
        rust_files(&root.join(core), &mut files);
    }
    files.push(root.join("scene.rs"));
    // The joystick mapping is pure too: only `input/gamepads.rs` talks to gilrs.
    for pure in ["map.rs", "controllers.rs"] {
        files.push(root.join("input").join(pure));
    }
    assert!(files.len() > 10);
    for f in files {
        let text = std::fs::read_to_string(&f).expect("read");
        for shell in [
            "wgpu",
            "winit",
            "egui",
            "gilrs",
            "rodio",
            "crate::render",
            "crate::cli",
        ] {
            assert!(
                !text.contains(shell),
                "{} mentions `{shell}`: the core must not depend on the shell",
                f.display()
            );
        }
    }
}

#[test]
fn every_shader_parses_and_validates() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut n = 0;
    for e in std::fs::read_dir(&dir).expect("shaders").flatten() {
        let p = e.path();
        if p.extension().is_none_or(|x| x != "wgsl") {
            continue;
        }
        let src = std::fs::read_to_string(&p).expect("read");
        let module = naga::front::wgsl::parse_str(&src)
            .unwrap_or_else(|e| panic!("{}: {}", p.display(), e.emit_to_string(&src)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::all(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}: {e:?}", p.display()));
        n += 1;
    }
    assert!(n >= 1, "no shaders found");
}
