//! Helpers shared by the command-line tests.
#![allow(dead_code)]

use std::path::Path;

/// A fresh directory in the system temp folder, removed when dropped
/// (`tempfile`); reads as a `Path`.
pub struct TempDir(tempfile::TempDir);

impl std::ops::Deref for TempDir {
    type Target = Path;
    fn deref(&self) -> &Path {
        self.0.path()
    }
}

/// A fresh temporary directory for the test `name`.
pub fn temp_dir(name: &str) -> TempDir {
    TempDir(
        tempfile::Builder::new()
            .prefix(&format!("proxima-cli-{name}-"))
            .tempdir()
            .unwrap(),
    )
}

/// Runs `proxima ARGS` with `env` under an address-space limit of `kib` KiB
/// (`ulimit -v`, as a container or a shared machine sets one): an
/// allocation past it fails and aborts the process (status 134), so a run
/// that ends with status 0 or 1 stayed below it. `PROXIMA_MEMORY_BUDGET` is
/// unset unless `env` sets it, so that the default budget is the one used.
pub fn proxima_under_limit(kib: u64, args: &[&str], env: &[(&str, &str)]) -> std::process::Output {
    let mut command = std::process::Command::new("sh");
    command
        .arg("-c")
        .arg(format!("ulimit -v {kib} && exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_proxima"))
        .args(args)
        .env_remove("PROXIMA_MEMORY_BUDGET");
    for (key, value) in env {
        command.env(key, value);
    }
    command.output().expect("run proxima under sh")
}

/// A GLB file of the JSON text `json` and the binary chunk `bin`, padded.
pub fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut json = json.as_bytes().to_vec();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut bin = bin.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(bin);
    out
}

/// One triangle's positions and a primitive of `corners` byte indices (0, 1,
/// 2, 0, …) of mode `mode`, shown by `nodes` nodes (no scene); `extra` is
/// inserted among the document's members, `node_extra` into the first node.
pub fn instanced_glb(corners: usize, nodes: usize, mode: u32, extra: &str, node_extra: &str) -> Vec<u8> {
    let mut bin: Vec<u8> = [0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    bin.extend((0..corners).map(|i| (i % 3) as u8));
    let nodes_json: Vec<String> = (0..nodes)
        .map(|i| {
            format!(
                r#"{{{}"mesh":0,"translation":[{i},0,0]}}"#,
                if i == 0 { node_extra } else { "" }
            )
        })
        .collect();
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},{extra}"buffers":[{{"byteLength":{}}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":{corners}}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"type":"VEC3","count":3}},
                     {{"bufferView":1,"componentType":5121,"type":"SCALAR","count":{corners}}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1,"mode":{mode}}}]}}],
        "nodes":[{}]}}"#,
        bin.len(),
        nodes_json.join(",")
    );
    glb(&json, &bin)
}
