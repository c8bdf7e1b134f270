//! The window's GPU state: the surface, the sphere renderer and egui's
//! renderer; made once the window exists, resized with it, and the painting
//! of one frame (the scene, then the HUD over it).

use std::sync::Arc;

use winit::event_loop::ActiveEventLoop;
use winit::window::Window;

use super::AppError;
use crate::render::spheres::{color_pass, depth_view};
use crate::render::{Gpu, RenderError, SphereRenderer, ViewParams};
use crate::session::Session;

/// The window and everything drawn into it.
pub struct Gfx {
    /// The window.
    pub window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    /// The device.
    pub gpu: Gpu,
    /// The surface's size and format.
    pub config: wgpu::SurfaceConfiguration,
    depth: wgpu::TextureView,
    /// Atoms.
    pub spheres: SphereRenderer,
    /// egui.
    pub egui_ctx: egui::Context,
    /// egui's winit glue.
    pub egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    /// Texture changes egui made that are not drawn yet.
    pub textures: PendingTextures,
}

/// egui's texture changes (glyph atlas, images) not yet given to the
/// renderer. A frame that draws nothing (a lost surface, a quit) keeps them
/// for the next, so no glyph goes missing; dropped, they are cleared, since
/// egui asserts in debug builds that every change it made was applied.
#[derive(Default)]
pub struct PendingTextures(pub egui::TexturesDelta);

impl Drop for PendingTextures {
    fn drop(&mut self) {
        self.0.clear();
    }
}

/// What a painted frame shows besides the session.
pub struct Paint<'a> {
    /// Lighting, cues, stereo.
    pub params: &'a ViewParams,
    /// The background colour (the contact flash changes it).
    pub background: [f64; 3],
    /// egui's shapes for this frame.
    pub shapes: Vec<egui::epaint::ClippedShape>,
    /// egui's scale.
    pub pixels_per_point: f32,
}

impl Gfx {
    /// Opens a `title`d window on `event_loop` with the GPU and renderers
    /// for `session`.
    ///
    /// # Errors
    /// [`AppError`] when no window, surface or device can be had.
    pub fn new(
        event_loop: &ActiveEventLoop,
        title: &str,
        session: &Session,
    ) -> Result<Self, AppError> {
        let attrs = Window::default_attributes()
            .with_title(title)
            .with_inner_size(winit::dpi::LogicalSize::new(1280.0, 800.0));
        let window = Arc::new(
            event_loop
                .create_window(attrs)
                .map_err(|e| AppError::EventLoop(e.to_string()))?,
        );
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
                Box::new(event_loop.owned_display_handle()),
            ));
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| RenderError::Device(e.to_string()))?;
        let gpu = Gpu::with_instance(instance, Some(&surface))?;
        let size = window.inner_size();
        let caps = surface.get_capabilities(&gpu.adapter);
        let format = caps
            .formats
            .iter()
            .copied()
            .find(wgpu::TextureFormat::is_srgb)
            .or_else(|| caps.formats.first().copied())
            .ok_or_else(|| RenderError::Device("the surface offers no format".into()))?;
        let mut config = surface
            .get_default_config(&gpu.adapter, size.width.max(1), size.height.max(1))
            .ok_or_else(|| RenderError::Device("the surface cannot be configured".into()))?;
        config.format = format;
        config.present_mode = wgpu::PresentMode::AutoVsync;
        surface.configure(&gpu.device, &config);
        let depth = depth_view(&gpu.device, config.width, config.height);
        let mut spheres = SphereRenderer::new(&gpu.device, format, session);
        spheres.sync_highlights(&gpu.queue, session);
        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(gpu.device.limits().max_texture_dimension_2d as usize),
        );
        let egui_renderer =
            egui_wgpu::Renderer::new(&gpu.device, format, egui_wgpu::RendererOptions::default());
        Ok(Self {
            window,
            surface,
            gpu,
            config,
            depth,
            spheres,
            egui_ctx,
            egui_state,
            egui_renderer,
            textures: PendingTextures::default(),
        })
    }

    /// Follows the window's new size.
    pub fn resize(&mut self, width: u32, height: u32) {
        self.config.width = width.max(1);
        self.config.height = height.max(1);
        self.surface.configure(&self.gpu.device, &self.config);
        self.depth = depth_view(&self.gpu.device, self.config.width, self.config.height);
        self.window.request_redraw();
    }

    /// A new sphere renderer for the session's molecules (files arrived).
    pub fn reload(&mut self, session: &Session, title: &str) {
        let mut spheres = SphereRenderer::new(&self.gpu.device, self.config.format, session);
        spheres.sync_highlights(&self.gpu.queue, session);
        self.spheres = spheres;
        self.window.set_title(title);
        self.window.request_redraw();
    }

    /// Draws `session` and the HUD and presents them; `false` when the
    /// surface gave no frame (it is reconfigured and a frame asked for).
    pub fn paint(&mut self, session: &Session, p: Paint<'_>) -> bool {
        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f)
            | wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.surface.configure(&self.gpu.device, &self.config);
                self.window.request_redraw();
                return false;
            }
            _ => return false,
        };
        let view = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        let mut encoder = self
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        self.spheres.draw_scene(
            &self.gpu.device,
            &self.gpu.queue,
            &mut encoder,
            &view,
            &self.depth,
            (self.config.width, self.config.height),
            session,
            p.params,
            p.background,
        );
        let extra = self.paint_hud(&mut encoder, &view, p.shapes, p.pixels_per_point);
        self.gpu
            .queue
            .submit(extra.into_iter().chain(Some(encoder.finish())));
        self.gpu.queue.present(frame);
        true
    }

    /// The HUD on top of the scene, with this frame's texture changes and
    /// those of frames that drew nothing.
    fn paint_hud(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        view: &wgpu::TextureView,
        shapes: Vec<egui::epaint::ClippedShape>,
        ppp: f32,
    ) -> Vec<wgpu::CommandBuffer> {
        let jobs = self.egui_ctx.tessellate(shapes, ppp);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [self.config.width, self.config.height],
            pixels_per_point: ppp,
        };
        let mut textures = std::mem::take(&mut self.textures.0);
        for (id, deltas) in textures.set.drain() {
            for delta in deltas {
                self.egui_renderer
                    .update_texture(&self.gpu.device, &self.gpu.queue, id, &delta);
            }
        }
        let extra = self.egui_renderer.update_buffers(
            &self.gpu.device,
            &self.gpu.queue,
            encoder,
            &jobs,
            &screen,
        );
        {
            let pass = color_pass(encoder, "hud", view, wgpu::LoadOp::Load);
            self.egui_renderer
                .render(&mut pass.forget_lifetime(), &jobs, &screen);
        }
        for id in textures.free.drain() {
            self.egui_renderer.free_texture(&id);
        }
        extra
    }
}

#[cfg(test)]
mod tests {
    use super::PendingTextures;

    /// Texture changes kept for a frame that never came (the window closed)
    /// are dropped without tripping egui's debug assertion, which a bare
    /// `TexturesDelta` would (a quit right after a message with new glyphs
    /// did, in a debug build).
    #[test]
    fn texture_changes_never_drawn_are_dropped_quietly() {
        let mut pending = PendingTextures::default();
        let mut delta = egui::TexturesDelta::default();
        delta.set.insert(
            egui::TextureId::Managed(0),
            [egui::epaint::ImageDelta::full(
                egui::ColorImage::filled([2, 2], egui::Color32::WHITE),
                egui::TextureOptions::LINEAR,
            )]
            .into_iter()
            .collect(),
        );
        pending.0.append(delta);
        assert_eq!(pending.0.set.len(), 1);
        drop(pending);
    }
}
