//! Small binary glTF files written by hand, for the loaders' hostile-input
//! tests (shared by the library's and the command line's tests).
#![allow(dead_code)]

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
