//! The sphere-impostor renderer: its GPU buffers and one frame's passes.
//!
//! Buffers: atoms (local position, radius, colour, molecule; written once),
//! one model-view matrix per molecule (rewritten each frame: a few bytes),
//! a four-bit highlight level per atom (only changed words rewritten), and
//! a small uniform per eye (projection, eye offset, light, cue settings). One
//! instanced draw call draws every atom of an eye. [`UploadStats`] counts
//! what was written, so tests can check that moving a molecule uploads no
//! atom data; [`FrameStats`] counts the passes and draws of the last frame,
//! so tests can check that a cue that is off costs no pass or draw.
//!
//! A frame ([`SphereRenderer::draw_scene`]): the shadow map (shadows only);
//! the eyes the stereo plan asks for (one in mono), each into its viewport
//! of the target or, for interleaved and anaglyph modes, into its own
//! texture; the screen-space pass (outlines, occlusion only) over each eye;
//! the composition (composed modes only).
//!
//! The ghost ([`super::ghost`]) adds one model-view matrix after the
//! molecules' and two draws of the drug's atoms per eye: the drug's own, or,
//! when its torsions are not the reference's, the ghost's copy of them at
//! the reference's (its own buffer and bind groups, written when the
//! reference or the radii change). The clipping slab ([`super::slab`]) is
//! two depths in the eye's uniform.

use bytemuck::{Pod, Zeroable};
use glam::{DMat4, DQuat, DVec3, Mat4, Vec3};
use wgpu::util::DeviceExt;

use super::colors;
use super::cylinders::Cylinders;
use super::ghost::{ghost_pose, ghost_torsions};
use super::pipelines::{Pipelines, Role, SHADOW_SIZE, SphereKey, sphere_layout};
use super::stereo::{EyeView, off_axis};
use super::view::{ViewParams, depth_range_for, model_views, perspective, scene_sphere};
use crate::motion::Pose;
use crate::session::{Reshaped, Session};

/// Depth buffer format.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// A render pass over `view` with no depth attachment: the HUD, and the
/// full-screen post and composition passes. `load` is what the pass starts
/// from (the frame so far, or a clear colour).
pub fn color_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    view: &wgpu::TextureView,
    load: wgpu::LoadOp<wgpu::Color>,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load,
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// A depth buffer of `width`×`height` for the sphere pass (readable by the
/// screen-space pass).
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
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        })
        .create_view(&wgpu::TextureViewDescriptor::default())
}

/// Atoms per highlight word: each has four bits, its highlight level (0:
/// none, 1: in contact, up to [`crate::session::PRESS_LEVELS`]: pressed
/// into the soft band), read by the shaders' `contact_colour`.
const HIGHLIGHTS_PER_WORD: usize = 8;

/// Writes `items[i]` for every index in `dirty` (sorted, without repeats)
/// to `buffer`, one write per contiguous run of indices; returns the bytes
/// written.
fn write_runs<T: bytemuck::Pod>(
    queue: &wgpu::Queue,
    buffer: &wgpu::Buffer,
    items: &[T],
    dirty: &[usize],
) -> u64 {
    let mut bytes = 0;
    let mut k = 0;
    while k < dirty.len() {
        let start = dirty[k];
        let mut end = start;
        while k + 1 < dirty.len() && dirty[k + 1] == end + 1 {
            k += 1;
            end += 1;
        }
        let run = &items[start..=end];
        let offset = (start * std::mem::size_of::<T>()) as u64;
        queue.write_buffer(buffer, offset, bytemuck::cast_slice(run));
        bytes += std::mem::size_of_val(run) as u64;
        k += 1;
    }
    bytes
}

/// Bind group 0 of the sphere pipelines: the eye's uniform, the atoms,
/// the model-view matrices and the highlight levels, in binding order.
fn sphere_bind_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    label: &str,
    buffers: [&wgpu::Buffer; 4],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry<'_>> = buffers
        .iter()
        .zip(0u32..)
        .map(|(b, binding)| wgpu::BindGroupEntry {
            binding,
            resource: b.as_entire_binding(),
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
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
    eye: [f32; 4],
    fog: [f32; 4],
    background: [f32; 4],
    light_view: [f32; 16],
    shadow: [f32; 4],
    shadow_b: [f32; 4],
    slab: [f32; 4],
    ghost: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct PostUniform {
    depth: [f32; 4],
    cue: [f32; 4],
}

/// What the last frame cost in passes and draw calls.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FrameStats {
    /// Eyes drawn (1 in mono and frame-sequential, 2 in the other stereo modes).
    pub eyes: u32,
    /// Render passes recorded.
    pub passes: u32,
    /// Draw calls recorded.
    pub draws: u32,
}

/// Optional GPU resources that exist (made on first use of their cue).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Resources {
    /// The shadow map.
    pub shadow_map: bool,
    /// The screen-space pass.
    pub post: bool,
    /// Eye textures for composed stereo modes.
    pub eye_textures: bool,
}

/// Bytes written to the GPU since the renderer was made, by kind.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct UploadStats {
    /// Atom positions, radii and colours (written once, at creation).
    pub atom_bytes: u64,
    /// Model-view matrices and the frame uniform.
    pub matrix_bytes: u64,
    /// Highlight levels (four bits an atom).
    pub highlight_bytes: u64,
    /// Atom colours rewritten (colour by contribution).
    pub color_bytes: u64,
    /// Atom radii rewritten (balls of ball-and-stick).
    pub radius_bytes: u64,
    /// Atom positions rewritten (torsions turned).
    pub position_bytes: u64,
    /// The ghost's own atoms (its reference conformation) written.
    pub ghost_bytes: u64,
}

/// The ghost's own atoms: the drug's, placed at the reference torsions.
struct GhostAtoms {
    /// What they were made of: the drug, the reference torsions and the
    /// radius generation.
    key: (usize, Vec<f64>, u64),
    /// Atoms written.
    count: u32,
    /// Atoms the buffer holds.
    capacity: usize,
    buf: wgpu::Buffer,
    /// Per eye: bind group 0 with the ghost's atoms in place of the scene's.
    eyes: [wgpu::BindGroup; 2],
}

/// Draws every atom of a session as ray-cast spheres.
pub struct SphereRenderer {
    pipelines: Pipelines,
    /// Per eye: its uniform and its bind group 0.
    eyes: [(wgpu::Buffer, wgpu::BindGroup); 2],
    mv_buf: wgpu::Buffer,
    hl_buf: wgpu::Buffer,
    atom_buf: wgpu::Buffer,
    /// The atoms as uploaded, so that a colour change rewrites whole atoms.
    atoms: Vec<GpuAtom>,
    /// Each atom's element colour, to go back to.
    element_colors: Vec<[f32; 3]>,
    /// Each atom's own radius, to go back to from a ball.
    radii: Vec<f32>,
    /// Bonds and dashes, made when the first stick is asked for.
    cylinders: Option<Cylinders>,
    n_atoms: u32,
    offsets: Vec<usize>,
    words: Vec<u32>,
    stats: UploadStats,
    last: FrameStats,
    /// A molecule drawn at a pose other than its session pose (a settle's
    /// animation).
    shown: Option<(usize, Pose)>,
    /// The layout of bind group 0 (for the ghost's own bind groups).
    layout: wgpu::BindGroupLayout,
    /// Counts radius changes (the ghost's copy follows them).
    radius_generation: u64,
    /// The ghost's own atoms, made when first needed.
    ghost: Option<GhostAtoms>,
}

/// Light, fog and shadow settings shared by the eyes of a frame.
struct Lighting {
    light: [f32; 4],
    fog: [f32; 4],
    light_view: [f32; 16],
    shadow: [f32; 4],
    shadow_b: [f32; 4],
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
        let words = vec![0u32; atoms.len().div_ceil(HIGHLIGHTS_PER_WORD)];
        let atom_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("atoms"),
            contents: bytemuck::cast_slice(&atoms),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        });
        let element_colors = atoms
            .iter()
            .map(|a| [a.color_body[0], a.color_body[1], a.color_body[2]])
            .collect();
        let radii = atoms.iter().map(|a| a.pos_radius[3]).collect();
        // One matrix per molecule and one for the ghost.
        let n_bodies = session.bodies().len() + 1;
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
        let layout = sphere_layout(device);
        let eye = |label| {
            let frame_buf = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: std::mem::size_of::<FrameUniform>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let bind_group = sphere_bind_group(
                device,
                &layout,
                label,
                [&frame_buf, &atom_buf, &mv_buf, &hl_buf],
            );
            (frame_buf, bind_group)
        };
        let eyes = [eye("first eye"), eye("second eye")];
        let mut pipelines = Pipelines::new(device, color_format, &layout);
        // The default (mono, depth-cued) pipeline is ready before the first frame.
        pipelines.sphere(
            device,
            SphereKey {
                role: Role::Opaque,
                depth_cue: true,
                shadow: false,
                ghost: false,
            },
        );
        let stats = UploadStats {
            atom_bytes: (atoms.len() * std::mem::size_of::<GpuAtom>()) as u64,
            ..UploadStats::default()
        };
        Self {
            pipelines,
            eyes,
            mv_buf,
            hl_buf,
            atom_buf,
            atoms,
            element_colors,
            radii,
            cylinders: None,
            n_atoms,
            offsets,
            words,
            stats,
            last: FrameStats::default(),
            shown: None,
            layout,
            radius_generation: 0,
            ghost: None,
        }
    }

    /// Light, fog and shadow settings of this frame (mono view space).
    fn lighting(session: &Session, params: &ViewParams) -> Lighting {
        let l = params.light.normalize_or(DVec3::Z);
        let (centre, radius) = scene_sphere(session);
        let cues = &params.cues;
        let fog = [
            (-centre.z - radius) as f32,
            (-centre.z + radius) as f32,
            if cues.depth {
                cues.depth_strength.clamp(0.0, 1.0)
            } else {
                0.0
            },
            0.0,
        ];
        // Light space: the light looks down −z at the scene's centre.
        let turn = DQuat::from_rotation_arc(l, DVec3::Z);
        let light_view = DMat4::from_quat(turn) * DMat4::from_translation(-centre);
        Lighting {
            light: [l.x as f32, l.y as f32, l.z as f32, params.ambient],
            fog,
            light_view: light_view.as_mat4().to_cols_array(),
            shadow: [radius as f32, radius as f32, (2.0 * radius) as f32, 0.15],
            shadow_b: [SHADOW_SIZE as f32, 0.85, 0.0, 0.0],
        }
    }

    /// Writes eye `k`'s uniform for `view`.
    #[allow(clippy::too_many_arguments)] // one eye's inputs, all needed
    fn write_eye(
        &mut self,
        queue: &wgpu::Queue,
        k: usize,
        view: &EyeView,
        session: &Session,
        params: &ViewParams,
        lit: &Lighting,
        background: [f64; 3],
    ) {
        let cam = session.view_camera();
        let (near, far) = depth_range_for(session, params);
        let x = params.stereo.eye_x(view.eye, cam.distance);
        let proj = if x == 0.0 {
            perspective(cam.fov_y, view.aspect, near, far)
        } else {
            let d = params.stereo.convergence_distance(cam.distance);
            off_axis(cam.fov_y, view.aspect, near, far, x, d)
        };
        let h = colors::HIGHLIGHT;
        let frame = FrameUniform {
            proj: proj.as_mat4().to_cols_array(),
            light: lit.light,
            highlight: [h[0], h[1], h[2], 1.0],
            eye: [x as f32, 0.0, 0.0, 0.0],
            fog: lit.fog,
            background: [
                background[0] as f32,
                background[1] as f32,
                background[2] as f32,
                1.0,
            ],
            light_view: lit.light_view,
            shadow: lit.shadow,
            shadow_b: lit.shadow_b,
            slab: match params.slab {
                Some(slab) => {
                    let (near, far) = slab.planes(session);
                    [near as f32, far as f32, 1.0, 0.0]
                }
                None => [0.0; 4],
            },
            ghost: {
                let t = params.ghost.unwrap_or_default().tint;
                [t[0], t[1], t[2], session.bodies().len() as f32]
            },
        };
        queue.write_buffer(&self.eyes[k].0, 0, bytemuck::bytes_of(&frame));
        self.stats.matrix_bytes += std::mem::size_of::<FrameUniform>() as u64;
    }

    /// Applies highlight changes `(molecule, atom, level)` (levels as
    /// [`Session::highlight_level`] gives them), rewriting only the 32-bit
    /// words that changed.
    pub fn apply_highlights(&mut self, queue: &wgpu::Queue, changes: &[(usize, usize, u8)]) {
        let mut dirty: Vec<usize> = Vec::new();
        for &(body, atom, level) in changes {
            let Some(&base) = self.offsets.get(body) else {
                continue;
            };
            let i = base + atom;
            let Some(word) = self.words.get_mut(i / HIGHLIGHTS_PER_WORD) else {
                continue;
            };
            let shift = 4 * (i % HIGHLIGHTS_PER_WORD);
            let level = u32::from(level.min(crate::session::PRESS_LEVELS));
            *word = (*word & !(0xF << shift)) | (level << shift);
            dirty.push(i / HIGHLIGHTS_PER_WORD);
        }
        dirty.sort_unstable();
        dirty.dedup();
        // Contiguous runs of dirty words go up in one write each.
        let bytes = write_runs(queue, &self.hl_buf, &self.words, &dirty);
        self.stats.highlight_bytes += bytes;
    }

    /// Recolours atoms: `(molecule, atom, colour)`, `None` for the
    /// element's colour. Only atoms whose colour differs are rewritten, in
    /// contiguous runs; returns how many atoms changed.
    pub fn set_colors(
        &mut self,
        queue: &wgpu::Queue,
        changes: &[(usize, usize, Option<[f32; 3]>)],
    ) -> usize {
        let mut dirty: Vec<usize> = Vec::new();
        for &(body, atom, color) in changes {
            let Some(&base) = self.offsets.get(body) else {
                continue;
            };
            let i = base + atom;
            let (Some(a), Some(e)) = (self.atoms.get_mut(i), self.element_colors.get(i)) else {
                continue;
            };
            let c = color.unwrap_or(*e);
            if a.color_body[..3] != c {
                a.color_body[..3].copy_from_slice(&c);
                dirty.push(i);
            }
        }
        let (n, bytes) = self.upload_atoms(queue, dirty);
        self.stats.color_bytes += bytes;
        n
    }

    /// Scales atoms' radii: `(molecule, atom, scale)` of the atom's own
    /// radius (ball-and-stick draws balls at a quarter). Only atoms whose
    /// radius differs are rewritten, in contiguous runs; returns how many
    /// atoms changed.
    pub fn set_radius_scales(
        &mut self,
        queue: &wgpu::Queue,
        changes: &[(usize, usize, f32)],
    ) -> usize {
        let mut dirty: Vec<usize> = Vec::new();
        for &(body, atom, scale) in changes {
            let Some(&base) = self.offsets.get(body) else {
                continue;
            };
            let i = base + atom;
            let (Some(a), Some(r)) = (self.atoms.get_mut(i), self.radii.get(i)) else {
                continue;
            };
            let radius = r * scale;
            if a.pos_radius[3] != radius {
                a.pos_radius[3] = radius;
                dirty.push(i);
            }
        }
        if !dirty.is_empty() {
            self.radius_generation += 1;
        }
        let (n, bytes) = self.upload_atoms(queue, dirty);
        self.stats.radius_bytes += bytes;
        n
    }

    /// Draws molecule `body` at `pose` rather than at its session pose
    /// (the frames of a settle's animation), or, with `None`, every
    /// molecule at its session pose again.
    pub fn show_pose(&mut self, shown: Option<(usize, Pose)>) {
        self.shown = shown;
    }

    /// Rewrites all of molecule `body`'s atom positions with `local` (its
    /// own frame, one per atom: a conformation on its way somewhere, as a
    /// settle's animation shows it). Returns how many atoms were
    /// rewritten; none when the count does not fit.
    pub fn set_local_positions(
        &mut self,
        queue: &wgpu::Queue,
        body: usize,
        local: &[Vec3],
    ) -> usize {
        let Some(&base) = self.offsets.get(body) else {
            return 0;
        };
        let end = self
            .offsets
            .get(body + 1)
            .copied()
            .unwrap_or(self.atoms.len());
        if end.saturating_sub(base) != local.len() {
            return 0;
        }
        for (a, p) in self.atoms[base..end].iter_mut().zip(local) {
            a.pos_radius[..3].copy_from_slice(&p.to_array());
        }
        let (n, bytes) = self.upload_atoms(queue, (base..end).collect());
        self.stats.position_bytes += bytes;
        n
    }

    /// Follows atoms that moved within their molecule (a torsion turned,
    /// was undone or reset, or the drug settled): rewrites only those
    /// atoms' positions, in contiguous runs (their colours, radii and
    /// highlights stay). Returns how many atoms were rewritten.
    pub fn set_positions(
        &mut self,
        queue: &wgpu::Queue,
        session: &Session,
        moved: &[Reshaped],
    ) -> usize {
        let mut dirty: Vec<usize> = Vec::new();
        for m in moved {
            let (Some(&base), Some(body)) =
                (self.offsets.get(m.body), session.bodies().get(m.body))
            else {
                continue;
            };
            for &atom in &m.atoms {
                let atom = atom as usize;
                let (Some(p), Some(a)) = (
                    body.molecule.local.get(atom),
                    self.atoms.get_mut(base + atom),
                ) else {
                    continue;
                };
                a.pos_radius[..3].copy_from_slice(&p.to_array());
                dirty.push(base + atom);
            }
        }
        let (n, bytes) = self.upload_atoms(queue, dirty);
        self.stats.position_bytes += bytes;
        n
    }

    /// Rewrites the atoms `dirty` (any order, repeats allowed) in
    /// contiguous runs; returns how many, and the bytes written.
    fn upload_atoms(&mut self, queue: &wgpu::Queue, mut dirty: Vec<usize>) -> (usize, u64) {
        dirty.sort_unstable();
        dirty.dedup();
        let bytes = write_runs(queue, &self.atom_buf, &self.atoms, &dirty);
        (dirty.len(), bytes)
    }

    /// The radius atom `atom` of molecule `body` is drawn with now (Å).
    pub fn radius_of(&self, body: usize, atom: usize) -> Option<f32> {
        let a = self.atoms.get(self.offsets.get(body)? + atom)?;
        Some(a.pos_radius[3])
    }

    /// The cylinders (bonds and dashes), made on first use.
    pub fn cylinders(&mut self, device: &wgpu::Device) -> &mut Cylinders {
        let format = self.pipelines.format();
        self.cylinders
            .get_or_insert_with(|| Cylinders::new(device, format))
    }

    /// The cylinders, if any were ever asked for.
    pub fn cylinders_made(&self) -> Option<&Cylinders> {
        self.cylinders.as_ref()
    }

    /// The colour atom `atom` of molecule `body` is drawn with now (linear
    /// RGB), if it exists.
    pub fn color_of(&self, body: usize, atom: usize) -> Option<[f32; 3]> {
        let a = self.atoms.get(self.offsets.get(body)? + atom)?;
        Some([a.color_body[0], a.color_body[1], a.color_body[2]])
    }

    /// Sets every highlight from the session (after loading, say).
    pub fn sync_highlights(&mut self, queue: &wgpu::Queue, session: &Session) {
        let mut changes = Vec::new();
        for (k, b) in session.bodies().iter().enumerate() {
            for i in 0..b.molecule.len() {
                changes.push((k, i, session.highlight_level(k, i)));
            }
        }
        self.apply_highlights(queue, &changes);
    }

    /// Makes the ghost's own atoms match drug `d`'s reference conformation
    /// when it is not the drug's current one; `true` when the ghost is to
    /// draw them, `false` when it draws the drug's own atoms.
    fn sync_ghost(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        session: &Session,
        d: usize,
    ) -> bool {
        let Some(torsions) = ghost_torsions(session, d) else {
            return false;
        };
        let key = (d, torsions, self.radius_generation);
        if self.ghost.as_ref().is_some_and(|g| g.key == key) {
            return true;
        }
        let (Some(&base), Some((local, _))) = (self.offsets.get(d), session.shape_at(d, &key.1))
        else {
            return false;
        };
        // The renderer's own count of the drug's atoms must be the shape's:
        // a renderer made for another session draws no ghost.
        let end = self.offsets.get(d + 1).copied().unwrap_or(self.atoms.len());
        if end.checked_sub(base) != Some(local.len()) {
            return false;
        }
        let Some(drug) = self.atoms.get(base..end) else {
            return false;
        };
        // The drug's atoms (radii as drawn now) at the reference's places.
        let atoms: Vec<GpuAtom> = drug
            .iter()
            .zip(&local)
            .map(|(a, p)| GpuAtom {
                pos_radius: [p.x, p.y, p.z, a.pos_radius[3]],
                color_body: a.color_body,
            })
            .collect();
        if atoms.is_empty() {
            return false;
        }
        let bytes = std::mem::size_of_val(atoms.as_slice());
        match &mut self.ghost {
            Some(g) if g.capacity >= atoms.len() => {
                queue.write_buffer(&g.buf, 0, bytemuck::cast_slice(&atoms));
                g.count = atoms.len() as u32;
                g.key = key;
            }
            _ => {
                let buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("ghost atoms"),
                    contents: bytemuck::cast_slice(&atoms),
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                });
                let eye = |k: usize| {
                    sphere_bind_group(
                        device,
                        &self.layout,
                        "ghost",
                        [&self.eyes[k].0, &buf, &self.mv_buf, &self.hl_buf],
                    )
                };
                let eyes = [eye(0), eye(1)];
                self.ghost = Some(GhostAtoms {
                    key,
                    count: atoms.len() as u32,
                    capacity: atoms.len(),
                    buf,
                    eyes,
                });
            }
        }
        self.stats.ghost_bytes += bytes as u64;
        true
    }

    /// Records one eye's draws into `pass` (its viewport already set);
    /// `ghost` is the drug's molecule index when its ghost is drawn, and
    /// whether it draws its own atoms ([`Self::sync_ghost`]).
    fn draw_eye(
        &mut self,
        device: &wgpu::Device,
        pass: &mut wgpu::RenderPass<'_>,
        k: usize,
        params: &ViewParams,
        ghost: Option<(usize, bool)>,
    ) {
        let cues = params.cues;
        let key = |role| SphereKey {
            role,
            depth_cue: cues.depth,
            shadow: cues.shadow,
            ghost: false,
        };
        pass.set_bind_group(0, &self.eyes[k].1, &[]);
        if cues.shadow {
            let shadow = self.pipelines.shadow(device);
            pass.set_bind_group(1, &shadow.bind_group, &[]);
        }
        let n = self.n_atoms;
        let split = self.offsets.get(1).map_or(n, |&o| o as u32);
        if cues.translucent && split < n {
            // The drug (every molecule but the first) opaque; then the
            // receptor's front surface alone in depth, then blended on top.
            pass.set_pipeline(self.pipelines.sphere(device, key(Role::Opaque)));
            pass.draw(0..6, split..n);
            // Sticks are opaque: drawn before the receptor's surface covers them.
            self.draw_sticks(device, pass, k, cues);
            pass.set_pipeline(self.pipelines.sphere(device, key(Role::DepthOnly)));
            pass.draw(0..6, 0..split);
            pass.set_pipeline(self.pipelines.sphere(device, key(Role::Translucent)));
            let a = f64::from(cues.opacity.clamp(0.0, 1.0));
            pass.set_blend_constant(wgpu::Color {
                r: a,
                g: a,
                b: a,
                a,
            });
            pass.draw(0..6, 0..split);
            self.last.draws += 3;
        } else {
            pass.set_pipeline(self.pipelines.sphere(device, key(Role::Opaque)));
            pass.draw(0..6, 0..n);
            self.last.draws += 1;
            self.draw_sticks(device, pass, k, cues);
        }
        if let (Some(g), Some((d, own))) = (params.ghost, ghost) {
            // The drug's atoms again at the reference pose: their front
            // surface into depth (where nothing is nearer), then blended
            // there, so overlapping ghost atoms blend once.
            let (first, end) = match (&self.ghost, own) {
                (Some(atoms), true) => {
                    pass.set_bind_group(0, &atoms.eyes[k], &[]);
                    (0, atoms.count)
                }
                _ => (
                    self.offsets.get(d).map_or(n, |&o| o as u32),
                    self.offsets.get(d + 1).map_or(n, |&o| o as u32),
                ),
            };
            let ghost_key = |role| SphereKey {
                ghost: true,
                ..key(role)
            };
            pass.set_pipeline(self.pipelines.sphere(device, ghost_key(Role::DepthOnly)));
            pass.draw(0..6, first..end);
            pass.set_pipeline(self.pipelines.sphere(device, ghost_key(Role::Translucent)));
            let a = f64::from(g.opacity.clamp(0.0, 1.0));
            pass.set_blend_constant(wgpu::Color {
                r: a,
                g: a,
                b: a,
                a,
            });
            pass.draw(0..6, first..end);
            self.last.draws += 2;
            pass.set_bind_group(0, &self.eyes[k].1, &[]);
        }
    }

    /// The bonds and dashes of eye `k`, if there are any (lit like the
    /// spheres, depth-cued with them; no shadow). The sticks' group 1
    /// replaces the shadow map's, which is bound again for the spheres
    /// drawn after them.
    fn draw_sticks(
        &mut self,
        device: &wgpu::Device,
        pass: &mut wgpu::RenderPass<'_>,
        k: usize,
        cues: super::Cues,
    ) {
        let Some(c) = &mut self.cylinders else {
            return;
        };
        let drawn = c.draw(device, pass, &self.eyes[k].1, cues.depth);
        self.last.draws += drawn;
        if drawn > 0 && cues.shadow {
            let shadow = self.pipelines.shadow(device);
            pass.set_bind_group(1, &shadow.bind_group, &[]);
        }
    }

    /// Records the eyes of `plan` into `color` (cleared to `background`),
    /// each in its viewport, and the screen-space pass over them.
    #[allow(clippy::too_many_arguments)] // one frame's inputs, all needed
    fn eye_pass(
        &mut self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        eyes: &[(usize, EyeView)],
        params: &ViewParams,
        background: [f64; 3],
        ghost: Option<(usize, bool)>,
    ) {
        let post = params.cues.needs_post();
        {
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
                        // Kept only for the screen-space pass.
                        store: if post {
                            wgpu::StoreOp::Store
                        } else {
                            wgpu::StoreOp::Discard
                        },
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            self.last.passes += 1;
            if self.n_atoms > 0 {
                for (k, view) in eyes {
                    let [x, y, w, h] = view.viewport;
                    pass.set_viewport(x as f32, y as f32, w as f32, h as f32, 0.0, 1.0);
                    self.draw_eye(device, &mut pass, *k, params, ghost);
                }
            }
        }
        if post && self.n_atoms > 0 {
            let format = self.pipelines.format();
            let cues = params.cues;
            let p = self.pipelines.post(device);
            let bind_group = p.bind_group(device, depth);
            let pipeline = p.pipeline(device, format, cues.outline, cues.ao);
            let mut pass = color_pass(encoder, "outlines and occlusion", color, wgpu::LoadOp::Load);
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.draw(0..3, 0..1);
            self.last.passes += 1;
            self.last.draws += 1;
        }
    }

    /// Records a whole frame of `session` into `color` (`width`×`height`,
    /// the renderer's colour format) cleared to `background` (linear RGB):
    /// the cues and stereo mode of `params` (its aspect is ignored: each
    /// eye's comes from the stereo plan). `depth` is a
    /// [`depth_view`] of the same size.
    #[allow(clippy::too_many_arguments)] // one frame's inputs, all needed
    pub fn draw_scene(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        (width, height): (u32, u32),
        session: &Session,
        params: &ViewParams,
        background: [f64; 3],
    ) -> FrameStats {
        self.last = FrameStats::default();
        let plan = params.stereo.plan(width, height, params.frame);
        let lit = Self::lighting(session, params);
        for (k, view) in plan.eyes.iter().enumerate().take(2) {
            self.write_eye(queue, k, view, session, params, &lit, background);
        }
        self.last.eyes = plan.eyes.len().min(2) as u32;
        let mut mvs: Vec<[f32; 16]> = model_views(session)
            .iter()
            .map(Mat4::to_cols_array)
            .collect();
        if let Some((b, pose)) = self.shown
            && let Some(mv) = mvs.get_mut(b)
        {
            let view = session.view_camera().view_matrix();
            let model = DMat4::from_rotation_translation(pose.rotation, pose.translation);
            *mv = (view * model).as_mat4().to_cols_array();
        }
        // The ghost's matrix follows the molecules' (composed in f64 too).
        let ghost = params.ghost.and(ghost_pose(session)).map(|(d, pose)| {
            let view = session.view_camera().view_matrix();
            let model = DMat4::from_rotation_translation(pose.rotation, pose.translation);
            mvs.push((view * model).as_mat4().to_cols_array());
            d
        });
        let ghost = ghost.map(|d| (d, self.sync_ghost(device, queue, session, d)));
        if !mvs.is_empty() {
            queue.write_buffer(&self.mv_buf, 0, bytemuck::cast_slice(&mvs));
        }
        self.stats.matrix_bytes += (mvs.len() * 64) as u64;
        if params.cues.needs_post() {
            let (near, far) = depth_range_for(session, params);
            let cam = session.view_camera();
            let f = 1.0 / (0.5 * cam.fov_y).tan();
            let (vw, vh, aspect) = plan.eyes.first().map_or((width, height, 1.0), |e| {
                (e.viewport[2], e.viewport[3], e.aspect)
            });
            let post = PostUniform {
                depth: [
                    near as f32,
                    far as f32,
                    (f / aspect * f64::from(vw) / 2.0) as f32,
                    (f * f64::from(vh) / 2.0) as f32,
                ],
                // Outline: depth jumps over 1 Å, 85 % dark. Occlusion: 3 Å, 70 %.
                cue: [1.0, 0.85, 3.0, 0.7],
            };
            let p = self.pipelines.post(device);
            queue.write_buffer(&p.uniform, 0, bytemuck::bytes_of(&post));
            self.stats.matrix_bytes += std::mem::size_of::<PostUniform>() as u64;
        }
        if params.cues.shadow && self.n_atoms > 0 {
            let shadow = self.pipelines.shadow(device);
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("shadow map"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &shadow.view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&shadow.pipeline);
            pass.set_bind_group(0, &self.eyes[0].1, &[]);
            pass.draw(0..6, 0..self.n_atoms);
            self.last.passes += 1;
            self.last.draws += 1;
        }
        let eyes: Vec<(usize, EyeView)> = plan.eyes.iter().copied().enumerate().take(2).collect();
        match plan.compose {
            None => self.eye_pass(
                device, encoder, color, depth, &eyes, params, background, ghost,
            ),
            Some(mode) => {
                let format = self.pipelines.format();
                let targets = self.pipelines.compose(device, width, height).eyes.clone();
                for (e, target) in eyes.iter().zip(&targets) {
                    self.eye_pass(
                        device,
                        encoder,
                        target,
                        depth,
                        std::slice::from_ref(e),
                        params,
                        background,
                        ghost,
                    );
                }
                let c = self.pipelines.compose(device, width, height);
                let bind_group = c.bind_group.clone();
                let pipeline = c.pipeline(device, format, mode);
                let mut pass = color_pass(
                    encoder,
                    "stereo composition",
                    color,
                    wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                );
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, &bind_group, &[]);
                pass.draw(0..3, 0..1);
                self.last.passes += 1;
                self.last.draws += 1;
            }
        }
        self.last
    }

    /// Passes and draws of the last frame.
    pub fn frame_stats(&self) -> FrameStats {
        self.last
    }

    /// Which optional resources exist: each is made only when its cue or
    /// mode is first used.
    pub fn resources(&self) -> Resources {
        Resources {
            shadow_map: self.pipelines.shadow.is_some(),
            post: self.pipelines.post.is_some(),
            eye_textures: self.pipelines.compose.is_some(),
        }
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
