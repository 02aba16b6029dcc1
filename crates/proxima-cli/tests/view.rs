//! `proxima view` without a display, and its argument errors. (The rendering
//! itself is tested in `crates/proxima-viewer/tests/screenshot.rs`.)

use std::process::Command;

fn proxima() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_proxima"));
    c.env_remove("DISPLAY").env_remove("WAYLAND_DISPLAY");
    c
}

#[test]
fn without_a_display_view_says_so_in_one_line_and_fails() {
    for args in [
        vec!["view"],
        vec!["view", "--screenshot", "out.png", "--query", "-1,0,2"],
        vec!["view", "--animate"],
        vec!["view", "--animate", "rebuild", "--screenshot", "out.png"],
    ] {
        let out = proxima().args(&args).output().unwrap();
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.starts_with("proxima: no display"), "{err}");
        assert!(err.contains("proxima demo") && err.contains("--screenshot"), "{err}");
        assert!(out.stdout.is_empty());
    }
}

#[test]
fn bad_view_arguments_are_usage_errors() {
    for args in [
        vec!["view", "--query", "1,2"],
        vec!["view", "--show-cells", "0"],
        vec!["view", "--show-ray", "0,0,0,0,0,0"],
        vec!["view", "--primitives", "cells"],
        vec!["view", "--frames", "3"],
        vec!["view", "--size", "10x10"],
        vec!["view", "--slice", "w"],
        vec!["view", "--slice", "z,inf"],
        vec!["view", "--slice-sign", "parity"],
        vec!["view", "--camera", "0,120"],
        vec!["view", "--pairs", "both"],
        vec!["view", "--pair-pose", "1,2,3"],
        vec!["view", "--animate", "both"],
    ] {
        let out = proxima().args(&args).output().unwrap();
        assert_eq!(
            out.status.code(),
            Some(2),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}
