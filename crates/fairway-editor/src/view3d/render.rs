//! wgpu side of the 3D view: an `egui_wgpu::CallbackTrait` paint callback
//! (as in egui's `custom3d_wgpu` example). Each view renders its scene into
//! its own offscreen colour + depth target (4× MSAA) in `prepare`, and
//! `paint` draws that image into egui's render pass with one triangle. The
//! offscreen target gives every view a depth buffer of its own, whatever
//! the window's depth configuration, and lets several views (before/after
//! side by side) coexist in one frame.

use std::collections::HashMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use eframe::egui;
use eframe::egui_wgpu::{self, wgpu};
use wgpu::util::DeviceExt;

/// MSAA samples of the offscreen target.
pub const MSAA: u32 = 4;
const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Floats per vertex: position (3), normal (3), colour (4).
pub const VERTEX_FLOATS: usize = 10;

static NEXT_SCENE_ID: AtomicU64 = AtomicU64::new(1);

/// Geometry ready for the GPU, in coordinates relative to the origin its builder was given (e.g.
/// the `origin` of `scene::surface_scene`; f32 keeps its precision near the origin).
#[derive(Debug, Default)]
pub struct Scene {
    id: u64,
    /// Triangle vertices, [`VERTEX_FLOATS`] each.
    pub tri_vertices: Vec<f32>,
    /// Triangle indices.
    pub tri_indices: Vec<u32>,
    /// Line-list vertices (pairs), [`VERTEX_FLOATS`] each (normal unused).
    pub line_vertices: Vec<f32>,
}

impl Scene {
    /// An empty scene with a fresh identity.
    pub fn new() -> Self {
        Self {
            id: NEXT_SCENE_ID.fetch_add(1, Ordering::Relaxed),
            ..Default::default()
        }
    }

    /// Append a vertex to the triangles.
    pub fn tri_vertex(&mut self, p: [f32; 3], n: [f32; 3], c: [f32; 4]) {
        self.tri_vertices
            .extend_from_slice(&[p[0], p[1], p[2], n[0], n[1], n[2], c[0], c[1], c[2], c[3]]);
    }

    /// Append a line segment.
    pub fn line(&mut self, a: [f32; 3], b: [f32; 3], c: [f32; 4]) {
        for p in [a, b] {
            self.line_vertices
                .extend_from_slice(&[p[0], p[1], p[2], 0.0, 0.0, 1.0, c[0], c[1], c[2], c[3]]);
        }
    }

    /// Number of triangle vertices.
    pub fn n_tri_vertices(&self) -> usize {
        self.tri_vertices.len() / VERTEX_FLOATS
    }
}

/// Per-frame parameters of a view (all in scene coordinates).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Uniforms {
    /// World → clip, column major.
    pub view_proj: [f32; 16],
    /// Eye position.
    pub eye: [f32; 3],
    /// Unit direction towards the light.
    pub light: [f32; 3],
    /// Zebra axes (components of the reflected ray measured along them).
    pub axis_b: [f32; 3],
    /// Second zebra axis.
    pub axis_c: [f32; 3],
    /// 0 shaded, 1 isophotes, 2 zebra.
    pub mode: u32,
    /// Stripe width (radians).
    pub stripe: f32,
    /// Background colour (sRGB 0..1).
    pub background: [f32; 4],
}

impl Uniforms {
    fn bytes(&self) -> Vec<u8> {
        let mut f: Vec<f32> = Vec::with_capacity(40);
        f.extend_from_slice(&self.view_proj);
        for v in [self.eye, self.light, self.axis_b, self.axis_c] {
            f.extend_from_slice(&[v[0], v[1], v[2], 0.0]);
        }
        f.extend_from_slice(&[self.mode as f32, self.stripe, 2e-4, 0.0]);
        f32_bytes(&f)
    }
}

fn f32_bytes(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_ne_bytes()).collect()
}

fn u32_bytes(v: &[u32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_ne_bytes()).collect()
}

const UNIFORM_SIZE: u64 = (16 + 4 * 5) * 4;

struct ViewTarget {
    size: [u32; 2],
    msaa: wgpu::TextureView,
    resolve: wgpu::TextureView,
    depth: wgpu::TextureView,
    blit_group: wgpu::BindGroup,
    uniforms: wgpu::Buffer,
    uniform_group: wgpu::BindGroup,
    scene_id: u64,
    tri: Option<(wgpu::Buffer, wgpu::Buffer, u32)>,
    lines: Option<(wgpu::Buffer, u32)>,
}

/// Pipelines and per-view targets, stored in egui_wgpu's callback resources.
pub struct Renderer3d {
    surface: wgpu::RenderPipeline,
    lines: wgpu::RenderPipeline,
    blit: wgpu::RenderPipeline,
    uniform_layout: wgpu::BindGroupLayout,
    blit_layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    views: HashMap<u64, ViewTarget>,
}

/// Create the pipelines and register them with eframe's renderer. Returns
/// a description of the adapter for the UI.
pub fn install(rs: &egui_wgpu::RenderState) -> String {
    let r = Renderer3d::new(&rs.device, rs.target_format);
    rs.renderer.write().callback_resources.insert(r);
    let info = rs.adapter.get_info();
    format!("{} ({:?})", info.name, info.backend)
}

impl Renderer3d {
    fn new(device: &wgpu::Device, target: wgpu::TextureFormat) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("fairway3d"),
            source: wgpu::ShaderSource::Wgsl(include_str!("shader.wgsl").into()),
        });
        let uniform_layout = uniform_bind_group_layout(device);
        let blit_layout = blit_bind_group_layout(device);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("fairway3d"),
            bind_group_layouts: &[Some(&uniform_layout)],
            immediate_size: 0,
        });
        let blit_pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("fairway3d_blit"),
            bind_group_layouts: &[Some(&blit_layout)],
            immediate_size: 0,
        });
        let surface = scene_pipeline(
            device,
            &module,
            &layout,
            "fairway3d_surface",
            "vs_surface",
            "fs_surface",
            wgpu::PrimitiveTopology::TriangleList,
        );
        let lines = scene_pipeline(
            device,
            &module,
            &layout,
            "fairway3d_lines",
            "vs_line",
            "fs_line",
            wgpu::PrimitiveTopology::LineList,
        );
        let blit = blit_pipeline(device, &module, &blit_pl, target);
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("fairway3d_blit"),
            mag_filter: wgpu::FilterMode::Nearest,
            min_filter: wgpu::FilterMode::Nearest,
            ..Default::default()
        });
        Self {
            surface,
            lines,
            blit,
            uniform_layout,
            blit_layout,
            sampler,
            views: HashMap::new(),
        }
    }

    fn target(&mut self, device: &wgpu::Device, key: u64, size: [u32; 2]) -> &mut ViewTarget {
        let stale = self.views.get(&key).is_none_or(|t| t.size != size);
        if stale {
            let old = self.views.remove(&key);
            let tex = |label: &str, format, samples, usage| {
                device
                    .create_texture(&wgpu::TextureDescriptor {
                        label: Some(label),
                        size: wgpu::Extent3d {
                            width: size[0],
                            height: size[1],
                            depth_or_array_layers: 1,
                        },
                        mip_level_count: 1,
                        sample_count: samples,
                        dimension: wgpu::TextureDimension::D2,
                        format,
                        usage,
                        view_formats: &[],
                    })
                    .create_view(&Default::default())
            };
            let ra = wgpu::TextureUsages::RENDER_ATTACHMENT;
            let msaa = tex("fairway3d_msaa", COLOR, MSAA, ra);
            let resolve = tex("fairway3d_resolve", COLOR, 1, ra | wgpu::TextureUsages::TEXTURE_BINDING);
            let depth = tex("fairway3d_depth", DEPTH, MSAA, ra);
            let blit_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("fairway3d_blit"),
                layout: &self.blit_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(&resolve),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::Sampler(&self.sampler),
                    },
                ],
            });
            let (uniforms, uniform_group, scene_id, tri, lines) = match old {
                Some(o) => (o.uniforms, o.uniform_group, o.scene_id, o.tri, o.lines),
                None => {
                    let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some("fairway3d_uniforms"),
                        size: UNIFORM_SIZE,
                        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    });
                    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                        label: Some("fairway3d_uniforms"),
                        layout: &self.uniform_layout,
                        entries: &[wgpu::BindGroupEntry {
                            binding: 0,
                            resource: uniforms.as_entire_binding(),
                        }],
                    });
                    (uniforms, group, 0, None, None)
                }
            };
            self.views.insert(
                key,
                ViewTarget {
                    size,
                    msaa,
                    resolve,
                    depth,
                    blit_group,
                    uniforms,
                    uniform_group,
                    scene_id,
                    tri,
                    lines,
                },
            );
        }
        self.views.get_mut(&key).unwrap()
    }
}

/// Bind group layout of the per-view uniforms (group 0 of the scene pipelines).
fn uniform_bind_group_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("fairway3d_uniforms"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: std::num::NonZeroU64::new(UNIFORM_SIZE),
            },
            count: None,
        }],
    })
}

/// Bind group layout of the blit: the resolved colour texture and its sampler.
fn blit_bind_group_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("fairway3d_blit"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    multisampled: false,
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
        ],
    })
}

/// A scene pipeline (surface triangles or lines) into the offscreen MSAA colour + depth target.
fn scene_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    label: &str,
    vs: &str,
    fs: &str,
    topology: wgpu::PrimitiveTopology,
) -> wgpu::RenderPipeline {
    let vertex_layout = wgpu::VertexBufferLayout {
        array_stride: (VERTEX_FLOATS * 4) as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4],
    };
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(vs),
            buffers: &[Some(vertex_layout)],
            compilation_options: Default::default(),
        },
        primitive: wgpu::PrimitiveState {
            topology,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::LessEqual),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: wgpu::MultisampleState {
            count: MSAA,
            mask: !0,
            alpha_to_coverage_enabled: false,
        },
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(fs),
            targets: &[Some(wgpu::ColorTargetState {
                format: COLOR,
                blend: Some(wgpu::BlendState::ALPHA_BLENDING),
                write_mask: wgpu::ColorWrites::ALL,
            })],
            compilation_options: Default::default(),
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// The pipeline that draws a view's resolved image into egui's render pass with one triangle.
fn blit_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    blit_pl: &wgpu::PipelineLayout,
    target: wgpu::TextureFormat,
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("fairway3d_blit"),
        layout: Some(blit_pl),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_blit"),
            buffers: &[],
            compilation_options: Default::default(),
        },
        primitive: Default::default(),
        depth_stencil: None,
        // eframe's default `multisampling: 0` → egui's pass has 1 sample
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(if target.is_srgb() { "fs_blit_linear" } else { "fs_blit" }),
            targets: &[Some(wgpu::ColorTargetState {
                format: target,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
            compilation_options: Default::default(),
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// The paint callback of one 3D view.
pub struct ViewCallback {
    /// Identity of the view (one offscreen target per key).
    pub key: u64,
    /// What to draw.
    pub scene: Arc<Scene>,
    /// Camera and shading.
    pub uniforms: Uniforms,
    /// The view's rectangle (points).
    pub rect: egui::Rect,
}

impl egui_wgpu::CallbackTrait for ViewCallback {
    fn prepare(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        screen: &egui_wgpu::ScreenDescriptor,
        encoder: &mut wgpu::CommandEncoder,
        resources: &mut egui_wgpu::CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        // without our pipelines (e.g. a test renderer), draw nothing
        let Some(r) = resources.get_mut::<Renderer3d>() else {
            return vec![];
        };
        let ppp = screen.pixels_per_point;
        let size = [
            ((self.rect.width() * ppp).round() as u32).clamp(1, 8192),
            ((self.rect.height() * ppp).round() as u32).clamp(1, 8192),
        ];
        let (surface, lines) = (r.surface.clone(), r.lines.clone());
        let t = r.target(device, self.key, size);
        queue.write_buffer(&t.uniforms, 0, &self.uniforms.bytes());
        if t.scene_id != self.scene.id {
            let s = &self.scene;
            t.tri = (!s.tri_indices.is_empty()).then(|| {
                let vb = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("fairway3d_tri_vertices"),
                    contents: &f32_bytes(&s.tri_vertices),
                    usage: wgpu::BufferUsages::VERTEX,
                });
                let ib = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("fairway3d_tri_indices"),
                    contents: &u32_bytes(&s.tri_indices),
                    usage: wgpu::BufferUsages::INDEX,
                });
                (vb, ib, s.tri_indices.len() as u32)
            });
            t.lines = (!s.line_vertices.is_empty()).then(|| {
                let vb = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("fairway3d_lines"),
                    contents: &f32_bytes(&s.line_vertices),
                    usage: wgpu::BufferUsages::VERTEX,
                });
                (vb, (s.line_vertices.len() / VERTEX_FLOATS) as u32)
            });
            t.scene_id = s.id;
        }
        let bg = self.uniforms.background;
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("fairway3d"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &t.msaa,
                depth_slice: None,
                resolve_target: Some(&t.resolve),
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color {
                        r: bg[0] as f64,
                        g: bg[1] as f64,
                        b: bg[2] as f64,
                        a: bg[3] as f64,
                    }),
                    store: wgpu::StoreOp::Discard,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &t.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &t.uniform_group, &[]);
        if let Some((vb, ib, n)) = &t.tri {
            pass.set_pipeline(&surface);
            pass.set_vertex_buffer(0, vb.slice(..));
            pass.set_index_buffer(ib.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..*n, 0, 0..1);
        }
        if let Some((vb, n)) = &t.lines {
            pass.set_pipeline(&lines);
            pass.set_vertex_buffer(0, vb.slice(..));
            pass.draw(0..*n, 0..1);
        }
        drop(pass);
        vec![]
    }

    fn paint(
        &self,
        _info: egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
        resources: &egui_wgpu::CallbackResources,
    ) {
        let Some(r) = resources.get::<Renderer3d>() else { return };
        let Some(t) = r.views.get(&self.key) else { return };
        pass.set_pipeline(&r.blit);
        pass.set_bind_group(0, &t.blit_group, &[]);
        pass.draw(0..3, 0..1);
    }
}
