//! The OpenGL renderer of the 3D view: raw glow calls inside an egui paint
//! callback. It uploads and draws a [`DrawFrame`]: the mesh as indexed
//! triangles (optionally cut away on one side of a plane), each box set as
//! instanced `GL_LINES` of one unit cube, the signed-distance slice as one
//! textured quad, and the overlay from one small dynamic buffer. Buffers are uploaded again only
//! when their identity ([`crate::scene::next_id`]) changes.
//!
//! The picture is drawn into an offscreen framebuffer and copied to the
//! window; while its [`FrameKey`] stays the same (the panel is used but
//! nothing in the 3D view changed) only the copy is done, so a heavy scene
//! (the 871k-triangle dragon, 100k+ cells) does not slow down the panel.
//! While the camera moves, many boxes are drawn as one point each.
//!
//! This is the only module with `unsafe` code: glow's calls are `unsafe`
//! because the GL context must be current and the objects must belong to it.
//! egui_glow guarantees the first inside a paint callback; this renderer only
//! uses objects it created on the same context.
#![allow(unsafe_code)]

use crate::scene::{ColorVertex, DrawFrame, FrameKey, MeshBuffers, MeshVertex, unit_cube_lines};
use eframe::egui::PaintCallbackInfo;
use eframe::glow::{self, HasContext};
use std::collections::HashMap;

const MESH_VS: &str = r#"
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
uniform mat4 u_view_projection;
out vec3 v_normal;
out vec3 v_position;
void main() {
    v_normal = a_normal;
    v_position = a_position;
    gl_PointSize = 3.0;
    gl_Position = u_view_projection * vec4(a_position, 1.0);
}
"#;

const MESH_FS: &str = r#"
in vec3 v_normal;
in vec3 v_position;
uniform vec3 u_eye;
uniform vec4 u_color;
uniform vec4 u_clip;
out vec4 o_color;
void main() {
    // The half-space in front of the slice is cut away (u_clip = 0: nothing is).
    if (dot(vec4(v_position, 1.0), u_clip) > 0.0) {
        discard;
    }
    // Head light, lit from both sides (meshes are not always consistently oriented).
    vec3 n = normalize(v_normal);
    vec3 l = normalize(u_eye - v_position);
    float d = abs(dot(n, l));
    o_color = vec4(u_color.rgb * (0.25 + 0.75 * d), 1.0);
}
"#;

const LINE_VS: &str = r#"
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec4 a_color;
layout(location = 2) in float a_size;
uniform mat4 u_view_projection;
out vec4 v_color;
void main() {
    v_color = a_color;
    gl_PointSize = a_size;
    gl_Position = u_view_projection * vec4(a_position, 1.0);
}
"#;

const LINE_FS: &str = r#"
in vec4 v_color;
uniform int u_round;
out vec4 o_color;
void main() {
    if (u_round != 0 && length(gl_PointCoord - vec2(0.5)) > 0.5) {
        discard;
    }
    o_color = v_color;
}
"#;

const BOX_VS: &str = r#"
layout(location = 0) in vec3 a_corner;
layout(location = 1) in vec3 a_min;
layout(location = 2) in vec3 a_size;
uniform mat4 u_view_projection;
uniform float u_point_size;
void main() {
    gl_PointSize = u_point_size;
    gl_Position = u_view_projection * vec4(a_min + a_corner * a_size, 1.0);
}
"#;

const BOX_FS: &str = r#"
uniform vec4 u_color;
out vec4 o_color;
void main() {
    o_color = u_color;
}
"#;

const SLICE_VS: &str = r#"
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec2 a_uv;
uniform mat4 u_view_projection;
out vec2 v_uv;
void main() {
    v_uv = a_uv;
    gl_Position = u_view_projection * vec4(a_position, 1.0);
}
"#;

const SLICE_FS: &str = r#"
in vec2 v_uv;
uniform sampler2D u_texture;
out vec4 o_color;
void main() {
    o_color = vec4(texture(u_texture, v_uv).rgb, 1.0);
}
"#;

/// One corner of the slice quad: position and texture coordinate.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct SliceVertex {
    position: [f32; 3],
    uv: [f32; 2],
}

fn rgba(c: [u8; 4]) -> [f32; 4] {
    c.map(|x| x as f32 / 255.0)
}

struct GpuMesh {
    id: u64,
    vao: glow::VertexArray,
    vbo: glow::Buffer,
    ibo: glow::Buffer,
    index_count: i32,
    vertex_count: i32,
}

struct GpuBoxes {
    /// Unit cube edges × instances.
    vao: glow::VertexArray,
    /// One point per box at its centre, not instanced (the level of detail
    /// while the camera moves: llvmpipe spends about as long per instance
    /// as per point, so a plain point list is several times faster).
    points_vao: glow::VertexArray,
    instances: glow::Buffer,
    centers: glow::Buffer,
    count: i32,
    used: bool,
}

/// GPU programs and buffers of the 3D view.
pub struct Renderer {
    mesh_program: glow::Program,
    line_program: glow::Program,
    box_program: glow::Program,
    /// The frame's mesh and its coarse copy.
    meshes: Vec<GpuMesh>,
    cube: glow::Buffer,
    target: Option<Target>,
    /// The key and pixel size of the picture in `target`.
    cached: Option<(FrameKey, [i32; 2])>,
    /// Offscreen drawing failed once: draw straight to the window.
    direct: bool,
    boxes: HashMap<u64, GpuBoxes>,
    overlay_vao: glow::VertexArray,
    overlay_vbo: glow::Buffer,
    slice_program: glow::Program,
    slice_vao: glow::VertexArray,
    slice_vbo: glow::Buffer,
    /// The slice's texture and the identity of the image in it.
    slice_texture: Option<(u64, glow::Texture)>,
    embedded: bool,
}

/// The offscreen framebuffer the picture is drawn into.
struct Target {
    fbo: glow::Framebuffer,
    color: glow::Renderbuffer,
    depth: glow::Renderbuffer,
    size: [i32; 2],
}

unsafe fn compile(gl: &glow::Context, header: &str, vs: &str, fs: &str) -> Result<glow::Program, String> {
    unsafe {
        let program = gl.create_program()?;
        let mut shaders = Vec::new();
        for (kind, source) in [(glow::VERTEX_SHADER, vs), (glow::FRAGMENT_SHADER, fs)] {
            let shader = gl.create_shader(kind)?;
            gl.shader_source(shader, &format!("{header}\n{source}"));
            gl.compile_shader(shader);
            if !gl.get_shader_compile_status(shader) {
                return Err(format!("shader compilation failed: {}", gl.get_shader_info_log(shader)));
            }
            gl.attach_shader(program, shader);
            shaders.push(shader);
        }
        gl.link_program(program);
        if !gl.get_program_link_status(program) {
            return Err(format!("shader linking failed: {}", gl.get_program_info_log(program)));
        }
        for shader in shaders {
            gl.detach_shader(program, shader);
            gl.delete_shader(shader);
        }
        Ok(program)
    }
}

impl Renderer {
    /// Compiles the programs and creates the static buffers.
    pub fn new(gl: &glow::Context) -> Result<Self, String> {
        let embedded = gl.version().is_embedded;
        let header = if embedded {
            "#version 300 es\nprecision highp float;"
        } else {
            "#version 330 core"
        };
        unsafe {
            let mesh_program = compile(gl, header, MESH_VS, MESH_FS)?;
            let line_program = compile(gl, header, LINE_VS, LINE_FS)?;
            let box_program = compile(gl, header, BOX_VS, BOX_FS)?;
            let slice_program = compile(gl, header, SLICE_VS, SLICE_FS)?;
            let slice_vao = gl.create_vertex_array()?;
            let slice_vbo = gl.create_buffer()?;
            gl.bind_vertex_array(Some(slice_vao));
            gl.bind_buffer(glow::ARRAY_BUFFER, Some(slice_vbo));
            let slice_stride = size_of::<SliceVertex>() as i32;
            gl.enable_vertex_attrib_array(0);
            gl.vertex_attrib_pointer_f32(0, 3, glow::FLOAT, false, slice_stride, 0);
            gl.enable_vertex_attrib_array(1);
            gl.vertex_attrib_pointer_f32(1, 2, glow::FLOAT, false, slice_stride, 12);
            gl.bind_vertex_array(None);
            gl.bind_buffer(glow::ARRAY_BUFFER, None);
            let cube = gl.create_buffer()?;
            gl.bind_buffer(glow::ARRAY_BUFFER, Some(cube));
            gl.buffer_data_u8_slice(
                glow::ARRAY_BUFFER,
                bytemuck::cast_slice(&unit_cube_lines()),
                glow::STATIC_DRAW,
            );
            let overlay_vao = gl.create_vertex_array()?;
            let overlay_vbo = gl.create_buffer()?;
            gl.bind_vertex_array(Some(overlay_vao));
            gl.bind_buffer(glow::ARRAY_BUFFER, Some(overlay_vbo));
            let stride = size_of::<ColorVertex>() as i32;
            gl.enable_vertex_attrib_array(0);
            gl.vertex_attrib_pointer_f32(0, 3, glow::FLOAT, false, stride, 0);
            gl.enable_vertex_attrib_array(1);
            gl.vertex_attrib_pointer_f32(1, 4, glow::UNSIGNED_BYTE, true, stride, 12);
            gl.enable_vertex_attrib_array(2);
            gl.vertex_attrib_pointer_f32(2, 1, glow::FLOAT, false, stride, 16);
            gl.bind_vertex_array(None);
            gl.bind_buffer(glow::ARRAY_BUFFER, None);
            Ok(Self {
                mesh_program,
                line_program,
                box_program,
                meshes: Vec::new(),
                cube,
                target: None,
                cached: None,
                direct: false,
                boxes: HashMap::new(),
                overlay_vao,
                overlay_vbo,
                slice_program,
                slice_vao,
                slice_vbo,
                slice_texture: None,
                embedded,
            })
        }
    }

    /// Deletes every GL object.
    pub fn destroy(&mut self, gl: &glow::Context) {
        unsafe {
            for m in std::mem::take(&mut self.meshes) {
                Self::drop_mesh(gl, m);
            }
            for (_, b) in self.boxes.drain() {
                gl.delete_vertex_array(b.vao);
                gl.delete_vertex_array(b.points_vao);
                gl.delete_buffer(b.instances);
                gl.delete_buffer(b.centers);
            }
            self.drop_target(gl);
            gl.delete_program(self.mesh_program);
            gl.delete_program(self.line_program);
            gl.delete_program(self.box_program);
            gl.delete_buffer(self.cube);
            gl.delete_vertex_array(self.overlay_vao);
            gl.delete_buffer(self.overlay_vbo);
            gl.delete_program(self.slice_program);
            gl.delete_vertex_array(self.slice_vao);
            gl.delete_buffer(self.slice_vbo);
            if let Some((_, texture)) = self.slice_texture.take() {
                gl.delete_texture(texture);
            }
        }
    }

    /// Uploads the frame's slice picture when it is new, and frees the
    /// texture when no slice is drawn.
    unsafe fn upload_slice(&mut self, gl: &glow::Context, frame: &DrawFrame) -> Result<(), String> {
        let wanted = frame.slice.as_ref().map(|s| s.id);
        if self.slice_texture.map(|(id, _)| id) == wanted {
            return Ok(());
        }
        unsafe {
            if let Some((_, texture)) = self.slice_texture.take() {
                gl.delete_texture(texture);
            }
            let Some(image) = &frame.slice else {
                return Ok(());
            };
            let texture = gl.create_texture()?;
            gl.active_texture(glow::TEXTURE0);
            gl.bind_texture(glow::TEXTURE_2D, Some(texture));
            gl.tex_image_2d(
                glow::TEXTURE_2D,
                0,
                glow::RGBA8 as i32,
                image.size[0] as i32,
                image.size[1] as i32,
                0,
                glow::RGBA,
                glow::UNSIGNED_BYTE,
                glow::PixelUnpackData::Slice(Some(bytemuck::cast_slice(&image.pixels))),
            );
            // Linear filtering between cell centres: texel centres sit on
            // the sampled points, so the colours interpolate the values.
            for (parameter, value) in [
                (glow::TEXTURE_MIN_FILTER, glow::LINEAR),
                (glow::TEXTURE_MAG_FILTER, glow::LINEAR),
                (glow::TEXTURE_WRAP_S, glow::CLAMP_TO_EDGE),
                (glow::TEXTURE_WRAP_T, glow::CLAMP_TO_EDGE),
            ] {
                gl.tex_parameter_i32(glow::TEXTURE_2D, parameter, value as i32);
            }
            gl.bind_texture(glow::TEXTURE_2D, None);
            self.slice_texture = Some((image.id, texture));
        }
        Ok(())
    }

    unsafe fn drop_mesh(gl: &glow::Context, m: GpuMesh) {
        unsafe {
            gl.delete_vertex_array(m.vao);
            gl.delete_buffer(m.vbo);
            gl.delete_buffer(m.ibo);
        }
    }

    /// Uploads the frame's mesh and its coarse copy (both, so that starting
    /// and stopping the camera switches without an upload) and frees others.
    unsafe fn upload_meshes(&mut self, gl: &glow::Context, frame: &DrawFrame) -> Result<(), String> {
        let wanted: Vec<&MeshBuffers> = frame.mesh.iter().chain(&frame.mesh_lod).map(|m| m.as_ref()).collect();
        let (keep, stale): (Vec<GpuMesh>, Vec<GpuMesh>) = std::mem::take(&mut self.meshes)
            .into_iter()
            .partition(|m| wanted.iter().any(|w| w.id == m.id));
        self.meshes = keep;
        for m in stale {
            unsafe { Self::drop_mesh(gl, m) };
        }
        for buffers in wanted {
            if self.meshes.iter().any(|m| m.id == buffers.id) {
                continue;
            }
            unsafe {
                let vao = gl.create_vertex_array()?;
                let vbo = gl.create_buffer()?;
                let ibo = gl.create_buffer()?;
                gl.bind_vertex_array(Some(vao));
                gl.bind_buffer(glow::ARRAY_BUFFER, Some(vbo));
                gl.buffer_data_u8_slice(
                    glow::ARRAY_BUFFER,
                    bytemuck::cast_slice(&buffers.vertices),
                    glow::STATIC_DRAW,
                );
                let stride = size_of::<MeshVertex>() as i32;
                gl.enable_vertex_attrib_array(0);
                gl.vertex_attrib_pointer_f32(0, 3, glow::FLOAT, false, stride, 0);
                gl.enable_vertex_attrib_array(1);
                gl.vertex_attrib_pointer_f32(1, 3, glow::FLOAT, false, stride, 12);
                gl.bind_buffer(glow::ELEMENT_ARRAY_BUFFER, Some(ibo));
                gl.buffer_data_u8_slice(
                    glow::ELEMENT_ARRAY_BUFFER,
                    bytemuck::cast_slice(&buffers.indices),
                    glow::STATIC_DRAW,
                );
                gl.bind_vertex_array(None);
                gl.bind_buffer(glow::ARRAY_BUFFER, None);
                gl.bind_buffer(glow::ELEMENT_ARRAY_BUFFER, None);
                self.meshes.push(GpuMesh {
                    id: buffers.id,
                    vao,
                    vbo,
                    ibo,
                    index_count: buffers.indices.len() as i32,
                    vertex_count: buffers.vertices.len() as i32,
                });
            }
        }
        Ok(())
    }

    unsafe fn upload_boxes(&mut self, gl: &glow::Context, frame: &DrawFrame) -> Result<(), String> {
        for b in self.boxes.values_mut() {
            b.used = false;
        }
        for layer in &frame.boxes {
            if let Some(b) = self.boxes.get_mut(&layer.set.id) {
                b.used = true;
                continue;
            }
            unsafe {
                let instances = gl.create_buffer()?;
                gl.bind_buffer(glow::ARRAY_BUFFER, Some(instances));
                gl.buffer_data_u8_slice(
                    glow::ARRAY_BUFFER,
                    bytemuck::cast_slice(&layer.set.boxes),
                    glow::STATIC_DRAW,
                );
                let vao = gl.create_vertex_array()?;
                gl.bind_vertex_array(Some(vao));
                gl.bind_buffer(glow::ARRAY_BUFFER, Some(self.cube));
                gl.enable_vertex_attrib_array(0);
                gl.vertex_attrib_pointer_f32(0, 3, glow::FLOAT, false, 12, 0);
                gl.bind_buffer(glow::ARRAY_BUFFER, Some(instances));
                for (location, offset) in [(1, 0), (2, 12)] {
                    gl.enable_vertex_attrib_array(location);
                    gl.vertex_attrib_pointer_f32(location, 3, glow::FLOAT, false, 24, offset);
                    gl.vertex_attrib_divisor(location, 1);
                }
                // Centres as `a_min` with the corner and size left at their
                // constant values (set before drawing).
                let centers_data: Vec<[f32; 3]> = layer
                    .set
                    .boxes
                    .iter()
                    .map(|b| std::array::from_fn(|k| b.min[k] + 0.5 * b.size[k]))
                    .collect();
                let centers = gl.create_buffer()?;
                let points_vao = gl.create_vertex_array()?;
                gl.bind_vertex_array(Some(points_vao));
                gl.bind_buffer(glow::ARRAY_BUFFER, Some(centers));
                gl.buffer_data_u8_slice(
                    glow::ARRAY_BUFFER,
                    bytemuck::cast_slice(&centers_data),
                    glow::STATIC_DRAW,
                );
                gl.enable_vertex_attrib_array(1);
                gl.vertex_attrib_pointer_f32(1, 3, glow::FLOAT, false, 12, 0);
                gl.bind_vertex_array(None);
                gl.bind_buffer(glow::ARRAY_BUFFER, None);
                self.boxes.insert(
                    layer.set.id,
                    GpuBoxes {
                        vao,
                        points_vao,
                        instances,
                        centers,
                        count: layer.set.boxes.len() as i32,
                        used: true,
                    },
                );
            }
        }
        // Sets no longer drawn are freed (a new grid replaces the old one).
        let stale: Vec<u64> = self.boxes.iter().filter(|(_, b)| !b.used).map(|(&id, _)| id).collect();
        for id in stale {
            if let Some(b) = self.boxes.remove(&id) {
                unsafe {
                    gl.delete_vertex_array(b.vao);
                    gl.delete_vertex_array(b.points_vao);
                    gl.delete_buffer(b.instances);
                    gl.delete_buffer(b.centers);
                }
            }
        }
        Ok(())
    }

    unsafe fn draw_colored(&self, gl: &glow::Context, mode: u32, vertices: &[ColorVertex], round: bool) {
        if vertices.is_empty() {
            return;
        }
        unsafe {
            gl.bind_vertex_array(Some(self.overlay_vao));
            gl.bind_buffer(glow::ARRAY_BUFFER, Some(self.overlay_vbo));
            gl.buffer_data_u8_slice(glow::ARRAY_BUFFER, bytemuck::cast_slice(vertices), glow::STREAM_DRAW);
            gl.uniform_1_i32(
                gl.get_uniform_location(self.line_program, "u_round").as_ref(),
                round as i32,
            );
            gl.draw_arrays(mode, 0, vertices.len() as i32);
        }
    }

    unsafe fn drop_target(&mut self, gl: &glow::Context) {
        if let Some(t) = self.target.take() {
            unsafe {
                gl.delete_framebuffer(t.fbo);
                gl.delete_renderbuffer(t.color);
                gl.delete_renderbuffer(t.depth);
            }
        }
        self.cached = None;
    }

    /// An offscreen framebuffer of `size` pixels (colour and depth).
    unsafe fn ensure_target(&mut self, gl: &glow::Context, size: [i32; 2]) -> Result<glow::Framebuffer, String> {
        if let Some(t) = &self.target
            && t.size == size
        {
            return Ok(t.fbo);
        }
        unsafe {
            self.drop_target(gl);
            let fbo = gl.create_framebuffer()?;
            let color = gl.create_renderbuffer()?;
            let depth = gl.create_renderbuffer()?;
            self.target = Some(Target {
                fbo,
                color,
                depth,
                size,
            });
            gl.bind_renderbuffer(glow::RENDERBUFFER, Some(color));
            gl.renderbuffer_storage(glow::RENDERBUFFER, glow::RGBA8, size[0], size[1]);
            gl.bind_renderbuffer(glow::RENDERBUFFER, Some(depth));
            gl.renderbuffer_storage(glow::RENDERBUFFER, glow::DEPTH_COMPONENT24, size[0], size[1]);
            gl.bind_renderbuffer(glow::RENDERBUFFER, None);
            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(fbo));
            gl.framebuffer_renderbuffer(
                glow::FRAMEBUFFER,
                glow::COLOR_ATTACHMENT0,
                glow::RENDERBUFFER,
                Some(color),
            );
            gl.framebuffer_renderbuffer(
                glow::FRAMEBUFFER,
                glow::DEPTH_ATTACHMENT,
                glow::RENDERBUFFER,
                Some(depth),
            );
            let status = gl.check_framebuffer_status(glow::FRAMEBUFFER);
            if status != glow::FRAMEBUFFER_COMPLETE {
                return Err(format!("offscreen framebuffer incomplete (status {status:#x})"));
            }
            Ok(fbo)
        }
    }

    /// Draws `frame` into the callback's rectangle of `window` (the
    /// framebuffer egui paints into): into the offscreen framebuffer when the
    /// picture changed, then copied. Leaves the state egui expects: its
    /// framebuffer, viewport and scissor, no depth test, no bound vertex array.
    pub fn paint(
        &mut self,
        gl: &glow::Context,
        frame: &DrawFrame,
        info: &PaintCallbackInfo,
        window: Option<glow::Framebuffer>,
        background: [u8; 4],
    ) -> Result<(), String> {
        let vp = info.viewport_in_pixels();
        let clip = info.clip_rect_in_pixels();
        let size = [vp.width_px, vp.height_px];
        if size[0] <= 0 || size[1] <= 0 {
            return Ok(());
        }
        unsafe {
            self.upload_meshes(gl, frame)?;
            self.upload_boxes(gl, frame)?;
            self.upload_slice(gl, frame)?;
            if self.direct {
                return self.draw(gl, frame, background);
            }
            let key = frame.key();
            let fresh = !frame.redraw && self.cached.as_ref().is_some_and(|(k, s)| *k == key && *s == size);
            let fbo = match self.ensure_target(gl, size) {
                Ok(fbo) => fbo,
                Err(_) => {
                    // Draw straight to the window from now on.
                    self.drop_target(gl);
                    self.direct = true;
                    gl.bind_framebuffer(glow::FRAMEBUFFER, window);
                    return self.draw(gl, frame, background);
                }
            };
            if !fresh {
                gl.bind_framebuffer(glow::FRAMEBUFFER, Some(fbo));
                gl.viewport(0, 0, size[0], size[1]);
                gl.disable(glow::SCISSOR_TEST);
                self.draw(gl, frame, background)?;
                self.cached = Some((key, size));
            }
            gl.bind_framebuffer(glow::READ_FRAMEBUFFER, Some(fbo));
            gl.bind_framebuffer(glow::DRAW_FRAMEBUFFER, window);
            gl.enable(glow::SCISSOR_TEST);
            gl.scissor(clip.left_px, clip.from_bottom_px, clip.width_px, clip.height_px);
            gl.blit_framebuffer(
                0,
                0,
                size[0],
                size[1],
                vp.left_px,
                vp.from_bottom_px,
                vp.left_px + size[0],
                vp.from_bottom_px + size[1],
                glow::COLOR_BUFFER_BIT,
                glow::NEAREST,
            );
            gl.bind_framebuffer(glow::FRAMEBUFFER, window);
            gl.viewport(vp.left_px, vp.from_bottom_px, size[0], size[1]);
        }
        Ok(())
    }

    /// Draws the picture into the bound framebuffer and viewport.
    unsafe fn draw(&mut self, gl: &glow::Context, frame: &DrawFrame, background: [u8; 4]) -> Result<(), String> {
        unsafe {
            let bg = rgba(background);
            gl.clear_color(bg[0], bg[1], bg[2], 1.0);
            gl.clear_depth_f32(1.0);
            gl.depth_mask(true);
            gl.clear(glow::COLOR_BUFFER_BIT | glow::DEPTH_BUFFER_BIT);
            gl.enable(glow::DEPTH_TEST);
            gl.depth_func(glow::LEQUAL);
            gl.disable(glow::BLEND);
            gl.disable(glow::CULL_FACE);
            if !self.embedded {
                gl.enable(glow::PROGRAM_POINT_SIZE);
            }
            let vp = frame.view_projection.to_cols_array();

            // The mesh, pushed back a little so lines and highlights on its
            // surface win the depth test.
            if let Some(buffers) = frame.mesh_drawn()
                && let Some(mesh) = self.meshes.iter().find(|m| m.id == buffers.id)
            {
                gl.use_program(Some(self.mesh_program));
                let p = self.mesh_program;
                gl.uniform_matrix_4_f32_slice(gl.get_uniform_location(p, "u_view_projection").as_ref(), false, &vp);
                gl.uniform_3_f32_slice(gl.get_uniform_location(p, "u_eye").as_ref(), &frame.eye.to_array());
                gl.uniform_4_f32_slice(
                    gl.get_uniform_location(p, "u_color").as_ref(),
                    &rgba(crate::scene::colors::MESH),
                );
                gl.uniform_4_f32_slice(gl.get_uniform_location(p, "u_clip").as_ref(), &frame.clip_plane);
                gl.bind_vertex_array(Some(mesh.vao));
                if mesh.index_count > 0 {
                    gl.enable(glow::POLYGON_OFFSET_FILL);
                    gl.polygon_offset(1.0, 1.0);
                    gl.draw_elements(glow::TRIANGLES, mesh.index_count, glow::UNSIGNED_INT, 0);
                    gl.disable(glow::POLYGON_OFFSET_FILL);
                }
                if frame.mesh_points {
                    gl.draw_arrays(glow::POINTS, 0, mesh.vertex_count);
                }
            }

            // The slice, pushed back like the mesh so that its zero contour wins.
            if let (Some(image), Some((id, texture))) = (&frame.slice, self.slice_texture)
                && image.id == id
            {
                let p = self.slice_program;
                gl.use_program(Some(p));
                gl.uniform_matrix_4_f32_slice(gl.get_uniform_location(p, "u_view_projection").as_ref(), false, &vp);
                gl.uniform_1_i32(gl.get_uniform_location(p, "u_texture").as_ref(), 0);
                gl.active_texture(glow::TEXTURE0);
                gl.bind_texture(glow::TEXTURE_2D, Some(texture));
                let c = image.corners;
                let corner = |k: usize, uv: [f32; 2]| SliceVertex {
                    position: c[k].to_array(),
                    uv,
                };
                let quad = [
                    corner(0, [0.0, 0.0]),
                    corner(1, [1.0, 0.0]),
                    corner(2, [1.0, 1.0]),
                    corner(0, [0.0, 0.0]),
                    corner(2, [1.0, 1.0]),
                    corner(3, [0.0, 1.0]),
                ];
                gl.bind_vertex_array(Some(self.slice_vao));
                gl.bind_buffer(glow::ARRAY_BUFFER, Some(self.slice_vbo));
                gl.buffer_data_u8_slice(glow::ARRAY_BUFFER, bytemuck::cast_slice(&quad), glow::STREAM_DRAW);
                gl.enable(glow::POLYGON_OFFSET_FILL);
                gl.polygon_offset(1.0, 1.0);
                gl.draw_arrays(glow::TRIANGLES, 0, 6);
                gl.disable(glow::POLYGON_OFFSET_FILL);
                gl.bind_texture(glow::TEXTURE_2D, None);
            }

            // Boxes: one instanced draw per set.
            let p = self.box_program;
            gl.use_program(Some(p));
            gl.uniform_matrix_4_f32_slice(gl.get_uniform_location(p, "u_view_projection").as_ref(), false, &vp);
            let color_location = gl.get_uniform_location(p, "u_color");
            let points = frame.boxes_as_points();
            gl.uniform_1_f32(gl.get_uniform_location(p, "u_point_size").as_ref(), 2.0);
            for layer in &frame.boxes {
                if let Some(b) = self.boxes.get(&layer.set.id)
                    && b.count > 0
                {
                    gl.uniform_4_f32_slice(color_location.as_ref(), &rgba(layer.color));
                    if points {
                        gl.bind_vertex_array(Some(b.points_vao));
                        gl.vertex_attrib_3_f32(0, 0.0, 0.0, 0.0);
                        gl.vertex_attrib_3_f32(2, 0.0, 0.0, 0.0);
                        gl.draw_arrays(glow::POINTS, 0, b.count);
                    } else {
                        gl.bind_vertex_array(Some(b.vao));
                        gl.draw_arrays_instanced(glow::LINES, 0, 24, b.count);
                    }
                }
            }

            // Overlay: highlights and lines depth-tested, markers on top.
            gl.use_program(Some(self.line_program));
            let p = self.line_program;
            gl.uniform_matrix_4_f32_slice(gl.get_uniform_location(p, "u_view_projection").as_ref(), false, &vp);
            let o = &frame.overlay;
            self.draw_colored(gl, glow::TRIANGLES, &o.triangles, false);
            self.draw_colored(gl, glow::LINES, &o.lines, false);
            self.draw_colored(gl, glow::POINTS, &o.points, true);
            gl.disable(glow::DEPTH_TEST);
            self.draw_colored(gl, glow::POINTS, &o.markers, true);

            if !self.embedded {
                gl.disable(glow::PROGRAM_POINT_SIZE);
            }
            gl.bind_vertex_array(None);
            gl.bind_buffer(glow::ARRAY_BUFFER, None);
            gl.use_program(None);
            gl.enable(glow::BLEND);
        }
        Ok(())
    }
}
