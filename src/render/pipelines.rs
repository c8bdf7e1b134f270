//! The render pipelines and their variants, made on first use.
//!
//! A depth cue that is off has no pipeline, texture or pass: variants are
//! chosen by [`SphereKey`] (depth cueing is a WGSL pipeline constant, the
//! shadowed fragment entry point is used only with shadows), and the shadow
//! map, the screen-space pass and the stereo composition are built only
//! when first asked for.

use std::collections::HashMap;

use super::spheres::DEPTH_FORMAT;
use super::stereo::Compose;

const SPHERES: &str = include_str!("../../shaders/spheres.wgsl");
const POST: &str = include_str!("../../shaders/post.wgsl");
const COMPOSE: &str = include_str!("../../shaders/compose.wgsl");

/// Side of the square shadow map, texels.
pub const SHADOW_SIZE: u32 = 2048;

/// What a sphere draw does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Role {
    /// Opaque atoms: colour and depth.
    Opaque,
    /// Depth only (the translucent receptor's front surface).
    DepthOnly,
    /// Colour blended over what is there, where depth is equal (the
    /// translucent receptor's front surface, after [`Role::DepthOnly`]).
    Translucent,
}

/// A sphere pipeline variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct SphereKey {
    /// What the draw does.
    pub role: Role,
    /// Depth cueing compiled in.
    pub depth_cue: bool,
    /// Shadow-map lookup compiled in (needs bind group 1).
    pub shadow: bool,
    /// The ghost: the drug's atoms at the reference pose, in one tint.
    pub ghost: bool,
}

fn uniform_entry(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn texture_entry(binding: u32, sample_type: wgpu::TextureSampleType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

/// Layout of bind group 0 of the sphere shader.
pub fn sphere_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
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
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("spheres"),
        entries: &[
            uniform_entry(0, wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT),
            storage(1),
            storage(2),
            storage(3),
        ],
    })
}

/// The shadow map and what reads it.
pub struct ShadowMap {
    /// The map (rendered into, then read).
    pub view: wgpu::TextureView,
    /// Bind group 1 of the shadowed sphere pipelines.
    pub bind_group: wgpu::BindGroup,
    /// The pipeline drawing the map.
    pub pipeline: wgpu::RenderPipeline,
}

/// The screen-space pass's layout, uniform and variants.
pub struct PostPass {
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    /// Its uniform.
    pub uniform: wgpu::Buffer,
    pipelines: HashMap<(bool, bool), wgpu::RenderPipeline>,
}

/// Two eye images and the composing pipelines.
pub struct ComposePass {
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    pipelines: HashMap<Compose, wgpu::RenderPipeline>,
    /// Size of the eye textures.
    pub size: (u32, u32),
    /// The eye images, first and second.
    pub eyes: [wgpu::TextureView; 2],
    /// Bind group reading both.
    pub bind_group: wgpu::BindGroup,
}

/// Every pipeline of the renderer, made when first needed.
pub struct Pipelines {
    format: wgpu::TextureFormat,
    module: wgpu::ShaderModule,
    plain_layout: wgpu::PipelineLayout,
    shadow_group_layout: wgpu::BindGroupLayout,
    shadowed_layout: wgpu::PipelineLayout,
    spheres: HashMap<SphereKey, wgpu::RenderPipeline>,
    /// The shadow map, once shadows were asked for.
    pub shadow: Option<ShadowMap>,
    /// The screen-space pass, once outlines or occlusion were asked for.
    pub post: Option<PostPass>,
    /// The stereo composition, once a composed mode was asked for.
    pub compose: Option<ComposePass>,
}

fn full_screen_pipeline(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    fs: &str,
    constants: &[(&str, f64)],
    target: wgpu::ColorTargetState,
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_full"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(fs),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants,
                ..Default::default()
            },
            targets: &[Some(target)],
        }),
        multiview_mask: None,
        cache: None,
    })
}

impl Pipelines {
    /// The sphere shader for colour targets of `format`, with `layout` as
    /// bind group 0.
    pub fn new(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        layout: &wgpu::BindGroupLayout,
    ) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("spheres.wgsl"),
            source: wgpu::ShaderSource::Wgsl(SPHERES.into()),
        });
        let plain_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("spheres"),
            bind_group_layouts: &[Some(layout)],
            immediate_size: 0,
        });
        let shadow_group_layout =
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("shadow map"),
                entries: &[texture_entry(0, wgpu::TextureSampleType::Depth)],
            });
        let shadowed_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("spheres, shadowed"),
            bind_group_layouts: &[Some(layout), Some(&shadow_group_layout)],
            immediate_size: 0,
        });
        Self {
            format,
            module,
            plain_layout,
            shadow_group_layout,
            shadowed_layout,
            spheres: HashMap::new(),
            shadow: None,
            post: None,
            compose: None,
        }
    }

    /// The sphere pipeline for `key`.
    pub fn sphere(&mut self, device: &wgpu::Device, key: SphereKey) -> &wgpu::RenderPipeline {
        let (module, format) = (&self.module, self.format);
        let layout = if key.shadow {
            &self.shadowed_layout
        } else {
            &self.plain_layout
        };
        self.spheres.entry(key).or_insert_with(|| {
            let (blend, write_mask, depth_write, compare) = match key.role {
                Role::Opaque => (
                    None,
                    wgpu::ColorWrites::ALL,
                    true,
                    wgpu::CompareFunction::Less,
                ),
                Role::DepthOnly => (
                    None,
                    wgpu::ColorWrites::empty(),
                    true,
                    wgpu::CompareFunction::Less,
                ),
                Role::Translucent => (
                    Some(wgpu::BlendState {
                        color: wgpu::BlendComponent {
                            src_factor: wgpu::BlendFactor::Constant,
                            dst_factor: wgpu::BlendFactor::OneMinusConstant,
                            operation: wgpu::BlendOperation::Add,
                        },
                        alpha: wgpu::BlendComponent::REPLACE,
                    }),
                    wgpu::ColorWrites::ALL,
                    false,
                    wgpu::CompareFunction::Equal,
                ),
            };
            let flag = |b: bool| if b { 1.0 } else { 0.0 };
            let constants = [
                ("DEPTH_CUE", flag(key.depth_cue)),
                ("GHOST", flag(key.ghost)),
            ];
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("spheres"),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some("vs_main"),
                    // GHOST picks the matrix, radius and colour here.
                    compilation_options: wgpu::PipelineCompilationOptions {
                        constants: &constants,
                        ..Default::default()
                    },
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(depth_write),
                    depth_compare: Some(compare),
                    stencil: wgpu::StencilState::default(),
                    bias: wgpu::DepthBiasState::default(),
                }),
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module,
                    entry_point: Some(if key.shadow { "fs_shadowed" } else { "fs_main" }),
                    compilation_options: wgpu::PipelineCompilationOptions {
                        constants: &constants,
                        ..Default::default()
                    },
                    targets: &[Some(wgpu::ColorTargetState {
                        format,
                        blend,
                        write_mask,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        })
    }

    /// The shadow map, made on first use.
    pub fn shadow(&mut self, device: &wgpu::Device) -> &ShadowMap {
        let (module, plain, group) = (&self.module, &self.plain_layout, &self.shadow_group_layout);
        self.shadow.get_or_insert_with(|| {
            let view = device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some("shadow map"),
                    size: wgpu::Extent3d {
                        width: SHADOW_SIZE,
                        height: SHADOW_SIZE,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: DEPTH_FORMAT,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                        | wgpu::TextureUsages::TEXTURE_BINDING,
                    view_formats: &[],
                })
                .create_view(&wgpu::TextureViewDescriptor::default());
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("shadow map"),
                layout: group,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&view),
                }],
            });
            let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("shadow map"),
                layout: Some(plain),
                vertex: wgpu::VertexState {
                    module,
                    entry_point: Some("vs_light"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState::default(),
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
                    entry_point: Some("fs_light"),
                    compilation_options: Default::default(),
                    targets: &[],
                }),
                multiview_mask: None,
                cache: None,
            });
            ShadowMap {
                view,
                bind_group,
                pipeline,
            }
        })
    }

    /// The screen-space pass, made on first use.
    pub fn post(&mut self, device: &wgpu::Device) -> &mut PostPass {
        self.post.get_or_insert_with(|| {
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("post"),
                entries: &[
                    uniform_entry(0, wgpu::ShaderStages::FRAGMENT),
                    texture_entry(1, wgpu::TextureSampleType::Depth),
                ],
            });
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("post"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("post.wgsl"),
                source: wgpu::ShaderSource::Wgsl(POST.into()),
            });
            let uniform = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("post"),
                size: 32,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            PostPass {
                layout,
                pipeline_layout,
                module,
                uniform,
                pipelines: HashMap::new(),
            }
        })
    }

    /// The composition of two `width`×`height` eye images, made (or
    /// resized) on first use.
    pub fn compose(&mut self, device: &wgpu::Device, width: u32, height: u32) -> &mut ComposePass {
        if self
            .compose
            .as_ref()
            .is_some_and(|c| c.size != (width, height))
            && let Some(old) = self.compose.take()
        {
            let fresh = ComposePass::with_eyes(device, self.format, old, width, height);
            self.compose = Some(fresh);
        }
        let format = self.format;
        self.compose.get_or_insert_with(|| {
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("compose"),
                entries: &[
                    texture_entry(0, wgpu::TextureSampleType::Float { filterable: false }),
                    texture_entry(1, wgpu::TextureSampleType::Float { filterable: false }),
                ],
            });
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("compose"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("compose.wgsl"),
                source: wgpu::ShaderSource::Wgsl(COMPOSE.into()),
            });
            let (eyes, bind_group) = eye_textures(device, format, &layout, width, height);
            ComposePass {
                layout,
                pipeline_layout,
                module,
                pipelines: HashMap::new(),
                size: (width, height),
                eyes,
                bind_group,
            }
        })
    }

    /// Colour format of the targets.
    pub fn format(&self) -> wgpu::TextureFormat {
        self.format
    }
}

fn eye_textures(
    device: &wgpu::Device,
    format: wgpu::TextureFormat,
    layout: &wgpu::BindGroupLayout,
    width: u32,
    height: u32,
) -> ([wgpu::TextureView; 2], wgpu::BindGroup) {
    let make = |label| {
        device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            })
            .create_view(&wgpu::TextureViewDescriptor::default())
    };
    let eyes = [make("first eye"), make("second eye")];
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("compose"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&eyes[0]),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&eyes[1]),
            },
        ],
    });
    (eyes, bind_group)
}

impl ComposePass {
    fn with_eyes(
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        old: ComposePass,
        width: u32,
        height: u32,
    ) -> Self {
        let (eyes, bind_group) = eye_textures(device, format, &old.layout, width, height);
        Self {
            size: (width, height),
            eyes,
            bind_group,
            ..old
        }
    }

    /// The composing pipeline for `mode`, writing `format`.
    pub fn pipeline(
        &mut self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        mode: Compose,
    ) -> &wgpu::RenderPipeline {
        let (layout, module) = (&self.pipeline_layout, &self.module);
        self.pipelines.entry(mode).or_insert_with(|| {
            let m = match mode {
                Compose::Rows => 0.0,
                Compose::Columns => 1.0,
                Compose::Anaglyph => 2.0,
            };
            full_screen_pipeline(
                device,
                "compose",
                layout,
                module,
                "fs_compose",
                &[("MODE", m)],
                wgpu::ColorTargetState {
                    format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                },
            )
        })
    }
}

impl PostPass {
    /// The pass variant with outlines and/or occlusion, writing `format`.
    pub fn pipeline(
        &mut self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        outline: bool,
        ao: bool,
    ) -> &wgpu::RenderPipeline {
        let (layout, module) = (&self.pipeline_layout, &self.module);
        self.pipelines.entry((outline, ao)).or_insert_with(|| {
            let flag = |b: bool| if b { 1.0 } else { 0.0 };
            // result = colour already there × the factor the shader writes.
            let multiply = wgpu::BlendState {
                color: wgpu::BlendComponent {
                    src_factor: wgpu::BlendFactor::Zero,
                    dst_factor: wgpu::BlendFactor::Src,
                    operation: wgpu::BlendOperation::Add,
                },
                alpha: wgpu::BlendComponent {
                    src_factor: wgpu::BlendFactor::Zero,
                    dst_factor: wgpu::BlendFactor::One,
                    operation: wgpu::BlendOperation::Add,
                },
            };
            full_screen_pipeline(
                device,
                "post",
                layout,
                module,
                "fs_post",
                &[("OUTLINE", flag(outline)), ("AO", flag(ao))],
                wgpu::ColorTargetState {
                    format,
                    blend: Some(multiply),
                    write_mask: wgpu::ColorWrites::ALL,
                },
            )
        })
    }

    /// A bind group reading `depth`.
    pub fn bind_group(&self, device: &wgpu::Device, depth: &wgpu::TextureView) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("post"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: self.uniform.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(depth),
                },
            ],
        })
    }
}
