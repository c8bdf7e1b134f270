//! The sphere-impostor pipeline and its GPU buffers.
//!
//! Buffers: atoms (local position, radius, colour, molecule; written once),
//! one model-view matrix per molecule (rewritten each frame: a few bytes),
//! one highlight bit per atom (only changed words rewritten), and a small
//! frame uniform (projection, light, highlight colour). One instanced draw
//! call draws every atom. [`UploadStats`] counts what was written, so tests
//! can check that moving a molecule uploads no atom data.

use bytemuck::{Pod, Zeroable};
use glam::Mat4;
use wgpu::util::DeviceExt;

use super::colors;
use super::view::{ViewParams, model_views, projection};
use crate::session::Session;

/// Depth buffer format.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

const SHADER: &str = include_str!("../../shaders/spheres.wgsl");

/// A depth buffer of `width`×`height` for the sphere pass.
pub fn depth_view(device: &wgpu::Device, width: u32, height: u32) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("depth"),
            size: wgpu::Extent3d {
                width: width.max(1),
                height: height.max(1),
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        })
        .create_view(&wgpu::TextureViewDescriptor::default())
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct GpuAtom {
    pos_radius: [f32; 4],
    color_body: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct FrameUniform {
    proj: [f32; 16],
    light: [f32; 4],
    highlight: [f32; 4],
}

/// Bytes written to the GPU since the renderer was made, by kind.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct UploadStats {
    /// Atom positions, radii and colours (written once, at creation).
    pub atom_bytes: u64,
    /// Model-view matrices and the frame uniform.
    pub matrix_bytes: u64,
    /// Highlight bits.
    pub highlight_bytes: u64,
}

/// Draws every atom of a session as ray-cast spheres.
pub struct SphereRenderer {
    pipeline: wgpu::RenderPipeline,
    bind_group: wgpu::BindGroup,
    frame_buf: wgpu::Buffer,
    mv_buf: wgpu::Buffer,
    hl_buf: wgpu::Buffer,
    n_atoms: u32,
    offsets: Vec<usize>,
    words: Vec<u32>,
    stats: UploadStats,
}

impl SphereRenderer {
    /// Builds the pipeline for `color_format` and uploads the session's atoms.
    pub fn new(
        device: &wgpu::Device,
        color_format: wgpu::TextureFormat,
        session: &Session,
    ) -> Self {
        let mut atoms = Vec::new();
        let mut offsets = Vec::new();
        for (k, b) in session.bodies().iter().enumerate() {
            offsets.push(atoms.len());
            for (p, a) in b.molecule.local.iter().zip(&b.molecule.atoms) {
                let c = colors::element(&a.element, k);
                atoms.push(GpuAtom {
                    pos_radius: [p.x, p.y, p.z, a.radius],
                    color_body: [c[0], c[1], c[2], k as f32],
                });
            }
        }
        let n_atoms = atoms.len() as u32;
        if atoms.is_empty() {
            atoms.push(GpuAtom::zeroed()); // a binding may not be empty
        }
        let words = vec![0u32; atoms.len().div_ceil(32)];
        let atom_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("atoms"),
            contents: bytemuck::cast_slice(&atoms),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let n_bodies = session.bodies().len().max(1);
        let mv_buf = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("model-view"),
            size: (n_bodies * 64) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let hl_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("highlight"),
            contents: bytemuck::cast_slice(&words),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        });
        let frame_buf = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame"),
            size: std::mem::size_of::<FrameUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let storage = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::VERTEX,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: true },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("spheres"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                storage(1),
                storage(2),
                storage(3),
            ],
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("spheres"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: frame_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: atom_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: mv_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: hl_buf.as_entire_binding(),
                },
            ],
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("spheres.wgsl"),
            source: wgpu::ShaderSource::Wgsl(SHADER.into()),
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("spheres"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("spheres"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: wgpu::StencilState::default(),
                bias: wgpu::DepthBiasState::default(),
            }),
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: color_format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        let stats = UploadStats {
            atom_bytes: (atoms.len() * std::mem::size_of::<GpuAtom>()) as u64,
            ..UploadStats::default()
        };
        Self {
            pipeline,
            bind_group,
            frame_buf,
            mv_buf,
            hl_buf,
            n_atoms,
            offsets,
            words,
            stats,
        }
    }

    /// Writes this frame's projection, light and model-view matrices.
    pub fn update_view(&mut self, queue: &wgpu::Queue, session: &Session, params: &ViewParams) {
        let light = params.light.normalize_or(glam::DVec3::Z).as_vec3();
        let h = colors::HIGHLIGHT;
        let frame = FrameUniform {
            proj: projection(session, params.aspect).to_cols_array(),
            light: [light.x, light.y, light.z, params.ambient],
            highlight: [h[0], h[1], h[2], 1.0],
        };
        queue.write_buffer(&self.frame_buf, 0, bytemuck::bytes_of(&frame));
        let mvs: Vec<[f32; 16]> = model_views(session)
            .iter()
            .map(Mat4::to_cols_array)
            .collect();
        if !mvs.is_empty() {
            queue.write_buffer(&self.mv_buf, 0, bytemuck::cast_slice(&mvs));
        }
        self.stats.matrix_bytes += (std::mem::size_of::<FrameUniform>() + mvs.len() * 64) as u64;
    }

    /// Applies highlight changes `(molecule, atom, in contact)`, rewriting
    /// only the 32-bit words that changed.
    pub fn apply_highlights(&mut self, queue: &wgpu::Queue, changes: &[(usize, usize, bool)]) {
        let mut dirty: Vec<usize> = Vec::new();
        for &(body, atom, on) in changes {
            let Some(&base) = self.offsets.get(body) else {
                continue;
            };
            let i = base + atom;
            let Some(word) = self.words.get_mut(i / 32) else {
                continue;
            };
            let bit = 1u32 << (i % 32);
            if on {
                *word |= bit;
            } else {
                *word &= !bit;
            }
            dirty.push(i / 32);
        }
        dirty.sort_unstable();
        dirty.dedup();
        // Contiguous runs of dirty words go up in one write each.
        let mut k = 0;
        while k < dirty.len() {
            let start = dirty[k];
            let mut end = start;
            while k + 1 < dirty.len() && dirty[k + 1] == end + 1 {
                k += 1;
                end += 1;
            }
            let words = &self.words[start..=end];
            queue.write_buffer(
                &self.hl_buf,
                (start * 4) as u64,
                bytemuck::cast_slice(words),
            );
            self.stats.highlight_bytes += (words.len() * 4) as u64;
            k += 1;
        }
    }

    /// Sets every highlight from the session (after loading, say).
    pub fn sync_highlights(&mut self, queue: &wgpu::Queue, session: &Session) {
        let mut changes = Vec::new();
        for (k, b) in session.bodies().iter().enumerate() {
            for i in 0..b.molecule.len() {
                changes.push((k, i, session.is_highlighted(k, i)));
            }
        }
        self.apply_highlights(queue, &changes);
    }

    /// Records the draw call into `pass`.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        if self.n_atoms == 0 {
            return;
        }
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.draw(0..6, 0..self.n_atoms);
    }

    /// Records a pass that clears `color` to `background` (linear RGB) and
    /// the depth buffer, then draws every atom.
    pub fn draw_scene(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        background: [f64; 3],
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("spheres"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: color,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color {
                        r: background[0],
                        g: background[1],
                        b: background[2],
                        a: 1.0,
                    }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
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
        self.draw(&mut pass);
    }

    /// What was uploaded so far.
    pub fn upload_stats(&self) -> UploadStats {
        self.stats
    }

    /// Number of atoms drawn.
    pub fn atom_count(&self) -> u32 {
        self.n_atoms
    }
}
