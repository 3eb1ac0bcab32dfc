//! The wgpu paint callback that draws the beam strips (`shaders/beams.wgsl`) inside egui's
//! render pass, its GPU resources (registered once in the renderer's callback resources), and
//! the egui-painter fallback used when no wgpu render state exists.

use std::sync::Arc;

use egui::{Painter, Rect};
use egui_wgpu::wgpu;
use egui_wgpu::{CallbackResources, CallbackTrait, RenderState, ScreenDescriptor};

use super::strips::{push_gpu_strip, push_mesh_strip, Polyline, StripVertex};

const SHADER: &str = include_str!("../../../shaders/beams.wgsl");

/// A strip to draw: polyline and half width in pixels.
pub struct Strip {
    /// The centre line.
    pub line: Polyline,
    /// Half width (physical pixels).
    pub half_px: f32,
}

/// GPU objects of the beam pipeline, kept in `egui_wgpu::Renderer::callback_resources`.
struct BeamResources {
    pipeline: wgpu::RenderPipeline,
    uniforms: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    vertices: wgpu::Buffer,
    capacity: u64,
    count: u32,
    /// The vertices last written to `vertices` (held, so that their address is not reused),
    /// not written again.
    uploaded: Option<Arc<Vec<StripVertex>>>,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Uniforms {
    screen_size: [f32; 2],
    srgb_target: u32,
    pad: u32,
}

/// Create the pipeline and register it with the renderer. Call once at start-up; returns
/// false if it could not be set up (then use the fallback).
pub fn init(rs: &RenderState) -> bool {
    let device = &rs.device;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("tsm_beams"),
        source: wgpu::ShaderSource::Wgsl(SHADER.into()),
    });
    let bgl = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("tsm_beams_bgl"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }],
    });
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("tsm_beams_layout"),
        bind_group_layouts: &[Some(&bgl)],
        immediate_size: 0,
    });
    let premultiplied = wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
        operation: wgpu::BlendOperation::Add,
    };
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("tsm_beams_pipeline"),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_main"),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<StripVertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x2, 1 => Float32x4, 2 => Float32x2],
            })],
            compilation_options: wgpu::PipelineCompilationOptions::default(),
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs_main"),
            targets: &[Some(wgpu::ColorTargetState {
                format: rs.target_format,
                blend: Some(wgpu::BlendState { color: premultiplied, alpha: premultiplied }),
                write_mask: wgpu::ColorWrites::ALL,
            })],
            compilation_options: wgpu::PipelineCompilationOptions::default(),
        }),
        multiview_mask: None,
        cache: None,
    });
    let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("tsm_beams_uniforms"),
        size: std::mem::size_of::<Uniforms>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("tsm_beams_bg"),
        layout: &bgl,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: uniforms.as_entire_binding(),
        }],
    });
    let capacity = 4096 * std::mem::size_of::<StripVertex>() as u64;
    let vertices = vertex_buffer(device, capacity);
    rs.renderer
        .write()
        .callback_resources
        .insert(BeamResources {
            pipeline,
            uniforms,
            bind_group,
            vertices,
            capacity,
            count: 0,
            uploaded: None,
        });
    true
}

fn vertex_buffer(device: &wgpu::Device, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("tsm_beams_vertices"),
        size,
        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// The paint callback: this frame's vertices.
struct BeamsCallback {
    vertices: Arc<Vec<StripVertex>>,
    srgb: bool,
}

impl CallbackTrait for BeamsCallback {
    fn prepare(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        screen: &ScreenDescriptor,
        _encoder: &mut wgpu::CommandEncoder,
        resources: &mut CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        let Some(res) = resources.get_mut::<BeamResources>() else {
            return Vec::new();
        };
        let bytes: &[u8] = bytemuck::cast_slice(self.vertices.as_slice());
        if bytes.len() as u64 > res.capacity {
            res.capacity = (bytes.len() as u64).next_power_of_two();
            res.vertices = vertex_buffer(device, res.capacity);
            res.uploaded = None;
        }
        let same = (res.uploaded.as_ref()).is_some_and(|u| Arc::ptr_eq(u, &self.vertices));
        if !bytes.is_empty() && !same {
            queue.write_buffer(&res.vertices, 0, bytes);
            res.uploaded = Some(Arc::clone(&self.vertices));
        }
        res.count = self.vertices.len() as u32;
        let u = Uniforms {
            screen_size: [
                screen.size_in_pixels[0] as f32 / screen.pixels_per_point,
                screen.size_in_pixels[1] as f32 / screen.pixels_per_point,
            ],
            srgb_target: u32::from(self.srgb),
            pad: 0,
        };
        queue.write_buffer(&res.uniforms, 0, bytemuck::bytes_of(&u));
        Vec::new()
    }

    fn paint(
        &self,
        info: egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
        resources: &CallbackResources,
    ) {
        let Some(res) = resources.get::<BeamResources>() else {
            return;
        };
        if res.count == 0 {
            return;
        }
        let [w, h] = info.screen_size_px;
        pass.set_viewport(0.0, 0.0, w as f32, h as f32, 0.0, 1.0);
        pass.set_pipeline(&res.pipeline);
        pass.set_bind_group(0, &res.bind_group, &[]);
        pass.set_vertex_buffer(0, res.vertices.slice(..));
        pass.draw(0..res.count, 0..1);
    }
}

/// The beams' geometry built for one view: vertices for the wgpu callback, or an egui mesh.
/// Kept while the view and the viewed increment stay the same, so a still frame builds nothing.
#[derive(Clone)]
pub enum Built {
    /// Vertices of the wgpu strips.
    Gpu(Arc<Vec<StripVertex>>),
    /// The egui-painter mesh.
    Mesh(Arc<egui::Mesh>),
}

/// Build the strips for the wgpu callback (`gpu`) or the egui painter, at `ppp` pixels a point.
pub fn build(strips: &[Strip], ppp: f32, gpu: bool) -> Built {
    if gpu {
        let mut v = Vec::new();
        for s in strips {
            push_gpu_strip(&s.line, s.half_px, ppp, &mut v);
        }
        Built::Gpu(Arc::new(v))
    } else {
        let mut mesh = egui::Mesh::default();
        for s in strips {
            push_mesh_strip(&s.line, s.half_px, ppp, &mut mesh);
        }
        Built::Mesh(Arc::new(mesh))
    }
}

/// Draw built strips clipped to `rect`: through the wgpu callback when `gpu` holds a render
/// state (and they were built for it), else with the egui painter.
pub fn paint(painter: &Painter, rect: Rect, built: &Built, gpu: Option<&RenderState>) {
    match (built, gpu) {
        (Built::Gpu(v), Some(rs)) => {
            painter.add(egui_wgpu::Callback::new_paint_callback(
                rect,
                BeamsCallback {
                    vertices: Arc::clone(v),
                    srgb: rs.target_format.is_srgb(),
                },
            ));
        }
        (Built::Mesh(m), _) => {
            painter.add(egui::Shape::mesh(Arc::clone(m)));
        }
        (Built::Gpu(_), None) => {}
    }
}
