//! Rendering without a window: to RGBA pixels, and to a PNG file written
//! atomically (a temporary file renamed into place, so a failure never leaves
//! half an image).

use std::path::Path;

use super::RenderError;
use super::colors::BACKGROUND;
use super::gpu::Gpu;
use super::spheres::{SphereRenderer, depth_view};
use super::view::ViewParams;
use crate::session::Session;

/// An 8-bit sRGB RGBA image.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Rows top to bottom, 4 bytes a pixel.
    pub rgba: Vec<u8>,
}

impl Image {
    /// The pixel at (x, y), or `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = ((y * self.width + x) * 4) as usize;
        Some([
            self.rgba[i],
            self.rgba[i + 1],
            self.rgba[i + 2],
            self.rgba[i + 3],
        ])
    }
}

/// Colour format of offscreen images.
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// An offscreen target of a fixed size with its renderer, reusable across
/// frames (for image tests and benchmarks).
pub struct Offscreen {
    color: wgpu::Texture,
    depth_view: wgpu::TextureView,
    readback: wgpu::Buffer,
    width: u32,
    height: u32,
    padded_row: u32,
    /// The sphere renderer drawing into it.
    pub spheres: SphereRenderer,
}

impl Offscreen {
    /// A `width`×`height` target for `session`'s molecules.
    ///
    /// # Errors
    /// [`RenderError::Size`] for a size outside 1..=8192.
    pub fn new(gpu: &Gpu, session: &Session, width: u32, height: u32) -> Result<Self, RenderError> {
        if !(1..=8192).contains(&width) || !(1..=8192).contains(&height) {
            return Err(RenderError::Size(width, height));
        }
        let size = wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        };
        let color = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("offscreen colour"),
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let padded_row = (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
            * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let readback = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: u64::from(padded_row) * u64::from(height),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut spheres = SphereRenderer::new(&gpu.device, FORMAT, session);
        spheres.sync_highlights(&gpu.queue, session);
        Ok(Self {
            color,
            depth_view: depth_view(&gpu.device, width, height),
            readback,
            width,
            height,
            padded_row,
            spheres,
        })
    }

    /// Draws the session as it stands and reads the image back.
    ///
    /// # Errors
    /// [`RenderError::Readback`] when the GPU cannot map the result.
    pub fn render(
        &mut self,
        gpu: &Gpu,
        session: &Session,
        params: &ViewParams,
    ) -> Result<Image, RenderError> {
        let view = self
            .color
            .create_view(&wgpu::TextureViewDescriptor::default());
        let mut encoder = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("offscreen"),
            });
        self.spheres.draw_scene(
            &gpu.device,
            &gpu.queue,
            &mut encoder,
            &view,
            &self.depth_view,
            (self.width, self.height),
            session,
            params,
            BACKGROUND,
        );
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &self.color,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &self.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.padded_row),
                    rows_per_image: Some(self.height),
                },
            },
            wgpu::Extent3d {
                width: self.width,
                height: self.height,
                depth_or_array_layers: 1,
            },
        );
        gpu.queue.submit(Some(encoder.finish()));
        let slice = self.readback.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| RenderError::Readback(e.to_string()))?;
        rx.recv()
            .map_err(|e| RenderError::Readback(e.to_string()))?
            .map_err(|e| RenderError::Readback(e.to_string()))?;
        let mut rgba = Vec::with_capacity((self.width * self.height * 4) as usize);
        {
            let data = slice
                .get_mapped_range()
                .map_err(|e| RenderError::Readback(e.to_string()))?;
            for row in data.chunks(self.padded_row as usize) {
                rgba.extend_from_slice(&row[..(self.width * 4) as usize]);
            }
        }
        self.readback.unmap();
        Ok(Image {
            width: self.width,
            height: self.height,
            rgba,
        })
    }
}

/// Renders `session` once at `width`×`height`.
///
/// # Errors
/// See [`Offscreen::new`] and [`Offscreen::render`].
pub fn render_image(
    gpu: &Gpu,
    session: &Session,
    width: u32,
    height: u32,
    params: &ViewParams,
) -> Result<Image, RenderError> {
    Offscreen::new(gpu, session, width, height)?.render(gpu, session, params)
}

/// Writes `image` as a PNG at `path`, atomically.
///
/// # Errors
/// [`RenderError::Write`] naming the file.
pub fn save_png(image: &Image, path: &Path) -> Result<(), RenderError> {
    let err = |reason: String| RenderError::Write {
        path: path.display().to_string(),
        reason,
    };
    let buf = image::RgbaImage::from_raw(image.width, image.height, image.rgba.clone())
        .ok_or_else(|| err("pixel buffer has the wrong size".into()))?;
    let mut png = std::io::Cursor::new(Vec::new());
    buf.write_to(&mut png, image::ImageFormat::Png)
        .map_err(|e| err(e.to_string()))?;
    crate::model::write::write_atomically(path, png.get_ref()).map_err(|e| err(e.reason))
}
