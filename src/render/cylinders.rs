//! Cylinder impostors (`shaders/cylinders.wgsl`): the bonds of the pocket
//! in ball-and-stick and the dashes of hydrogen bonds, in one instanced
//! draw call per eye.
//!
//! A [`Stick`] names two atoms of the sphere renderer (global indices) and
//! the part of the segment between them it covers, so a stick follows its
//! molecules' model-view matrices and its atoms' colours with no upload of
//! its own: the list is uploaded only when it changes. The list has two
//! parts, the bonds (changed when the pocket's set of atoms changes) and
//! the dashes (changed with the hydrogen bonds); a change of the dashes
//! rewrites only their part. Nothing is made (buffer, pipeline) before the
//! first stick is asked for, and an empty list costs no draw.

use std::collections::HashMap;

use bytemuck::{Pod, Zeroable};

use super::pipelines::sphere_layout;
use super::spheres::DEPTH_FORMAT;

const CYLINDERS: &str = include_str!("../../shaders/cylinders.wgsl");

/// One cylinder as the shader reads it.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Stick {
    /// First atom (global index in the sphere renderer).
    pub a: u32,
    /// Second atom.
    pub b: u32,
    /// Start of the covered part of a→b (0 at a).
    pub t0: f32,
    /// End of the covered part (1 at b).
    pub t1: f32,
    /// Radius, Å.
    pub radius: f32,
    /// Packed RGBA8 colour (linear, red in the low byte); 0: each half
    /// takes its atom's colour.
    pub color: u32,
    pad: [u32; 2],
}

impl Stick {
    /// A bond from atom `a` to atom `b`, each half in its atom's colour.
    pub fn bond(a: u32, b: u32, radius: f32) -> Self {
        Self::piece(a, b, (0.0, 1.0), radius, None)
    }

    /// The part `t0..t1` of the segment from atom `a` to atom `b`, in
    /// `color` (linear RGB) or, with `None`, in its atoms' colours.
    pub fn piece(
        a: u32,
        b: u32,
        (t0, t1): (f32, f32),
        radius: f32,
        color: Option<[f32; 3]>,
    ) -> Self {
        Self {
            a,
            b,
            t0,
            t1,
            radius,
            color: color.map_or(0, pack),
            pad: [0; 2],
        }
    }
}

/// Packs a linear RGB colour as RGBA8 (alpha 255, so never 0).
fn pack(c: [f32; 3]) -> u32 {
    let q = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u32;
    q(c[0]) | (q(c[1]) << 8) | (q(c[2]) << 16) | (255 << 24)
}

/// The cylinder pipeline, its stick buffer and the list uploaded.
pub struct Cylinders {
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    group_layout: wgpu::BindGroupLayout,
    format: wgpu::TextureFormat,
    pipelines: HashMap<bool, wgpu::RenderPipeline>,
    buffer: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    capacity: usize,
    bonds: Vec<Stick>,
    dashes: Vec<Stick>,
    /// Bytes of stick data uploaded so far.
    pub uploaded_bytes: u64,
}

const STICK_SIZE: usize = std::mem::size_of::<Stick>();

impl Cylinders {
    /// The pipeline layout and an empty list, for colour targets of `format`.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("cylinders.wgsl"),
            source: wgpu::ShaderSource::Wgsl(CYLINDERS.into()),
        });
        let group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sticks"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: true },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let spheres = sphere_layout(device);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("cylinders"),
            bind_group_layouts: &[Some(&spheres), Some(&group_layout)],
            immediate_size: 0,
        });
        let (buffer, bind_group) = Self::storage(device, &group_layout, 64);
        Self {
            module,
            layout,
            group_layout,
            format,
            pipelines: HashMap::new(),
            buffer,
            bind_group,
            capacity: 64,
            bonds: Vec::new(),
            dashes: Vec::new(),
            uploaded_bytes: 0,
        }
    }

    fn storage(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        capacity: usize,
    ) -> (wgpu::Buffer, wgpu::BindGroup) {
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sticks"),
            size: (capacity * STICK_SIZE) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sticks"),
            layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: buffer.as_entire_binding(),
            }],
        });
        (buffer, bind_group)
    }

    /// Makes room for `n` sticks; `true` when the buffer was replaced (its
    /// contents are gone).
    fn reserve(&mut self, device: &wgpu::Device, n: usize) -> bool {
        if n <= self.capacity {
            return false;
        }
        let capacity = n.next_power_of_two();
        (self.buffer, self.bind_group) = Self::storage(device, &self.group_layout, capacity);
        self.capacity = capacity;
        true
    }

    fn write(&mut self, queue: &wgpu::Queue, first: usize, sticks: &[Stick]) {
        if sticks.is_empty() {
            return;
        }
        queue.write_buffer(
            &self.buffer,
            (first * STICK_SIZE) as u64,
            bytemuck::cast_slice(sticks),
        );
        self.uploaded_bytes += std::mem::size_of_val(sticks) as u64;
    }

    /// Sets the bonds; uploads only when they differ from those drawn now
    /// (then the dashes after them too). Returns whether anything was
    /// uploaded.
    pub fn set_bonds(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        bonds: &[Stick],
    ) -> bool {
        if self.bonds == bonds {
            return false;
        }
        let old = self.bonds.len();
        self.bonds = bonds.to_vec();
        let replaced = self.reserve(device, self.bonds.len() + self.dashes.len());
        let bonds = std::mem::take(&mut self.bonds);
        self.write(queue, 0, &bonds);
        self.bonds = bonds;
        // The dashes follow the bonds: rewritten when they moved or the
        // buffer is new.
        if old != self.bonds.len() || replaced {
            let dashes = std::mem::take(&mut self.dashes);
            self.write(queue, self.bonds.len(), &dashes);
            self.dashes = dashes;
        }
        true
    }

    /// Sets the dashes; uploads only their part, only when they changed.
    pub fn set_dashes(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        dashes: &[Stick],
    ) -> bool {
        if self.dashes == dashes {
            return false;
        }
        self.dashes = dashes.to_vec();
        if self.reserve(device, self.bonds.len() + self.dashes.len()) {
            let bonds = std::mem::take(&mut self.bonds);
            self.write(queue, 0, &bonds);
            self.bonds = bonds;
        }
        let dashes = std::mem::take(&mut self.dashes);
        self.write(queue, self.bonds.len(), &dashes);
        self.dashes = dashes;
        true
    }

    /// Number of sticks drawn (bonds and dashes).
    pub fn len(&self) -> usize {
        self.bonds.len() + self.dashes.len()
    }

    /// True when nothing is drawn.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The bonds drawn now.
    pub fn bonds(&self) -> &[Stick] {
        &self.bonds
    }

    /// The dashes drawn now.
    pub fn dashes(&self) -> &[Stick] {
        &self.dashes
    }

    /// Records the draw of every stick into `pass`, with `eye` as bind
    /// group 0 (the sphere renderer's group of this eye). Returns the
    /// number of draw calls (0 or 1).
    pub fn draw(
        &mut self,
        device: &wgpu::Device,
        pass: &mut wgpu::RenderPass<'_>,
        eye: &wgpu::BindGroup,
        depth_cue: bool,
    ) -> u32 {
        let n = self.len() as u32;
        if n == 0 {
            return 0;
        }
        let pipeline = self.pipeline(device, depth_cue).clone();
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, eye, &[]);
        pass.set_bind_group(1, &self.bind_group, &[]);
        pass.draw(0..36, 0..n);
        1
    }

    fn pipeline(&mut self, device: &wgpu::Device, depth_cue: bool) -> &wgpu::RenderPipeline {
        let (module, layout, format) = (&self.module, &self.layout, self.format);
        self.pipelines.entry(depth_cue).or_insert_with(|| {
            let constants = [("DEPTH_CUE", if depth_cue { 1.0 } else { 0.0 })];
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("cylinders"),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some("vs_stick"),
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
                    module,
                    entry_point: Some("fs_stick"),
                    compilation_options: wgpu::PipelineCompilationOptions {
                        constants: &constants,
                        ..Default::default()
                    },
                    targets: &[Some(wgpu::ColorTargetState {
                        format,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stick_is_32_bytes_and_packs_its_colour() {
        assert_eq!(STICK_SIZE, 32);
        assert_eq!(pack([1.0, 0.0, 0.0]), 0xff00_00ff);
        assert_eq!(pack([0.0, 0.0, 1.0]), 0xffff_0000);
        assert_ne!(
            pack([0.0, 0.0, 0.0]),
            0,
            "a black stick is not 'atom colours'"
        );
        assert_eq!(Stick::bond(1, 2, 0.2).color, 0);
    }
}
