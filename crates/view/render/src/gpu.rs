//! Drawing a [`Scene`] with wgpu: a [`Renderer`] that records its draws into any render pass
//! (a window's, or an offscreen texture's), and [`Offscreen`], which renders to an image
//! without a display.

use crate::RenderError;
use crate::camera::Camera;
use crate::scene::{BACKGROUND, ColorVertex, MeshVertex, Scene};
use bytemuck::{Pod, Zeroable};
use std::time::Duration;

/// Depth format of offscreen views.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Colour format of offscreen views: bytes as they are, like the heatmaps' PNGs.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// Which adapter to render with.
#[derive(Clone, Debug, PartialEq)]
pub struct GpuOptions {
    /// Backends to try (the `WGPU_BACKEND` environment variable, `vulkan` or `gl`, overrides).
    pub backends: wgpu::Backends,
    /// Only a software adapter (Mesa's lavapipe or llvmpipe): the same pixels on every
    /// machine with the same Mesa, GPU or not.
    pub software: bool,
    /// Samples per pixel (1, or 4 for smoother edges where the adapter supports it).
    pub samples: u32,
}

impl Default for GpuOptions {
    fn default() -> Self {
        GpuOptions { backends: wgpu::Backends::VULKAN | wgpu::Backends::GL, software: false, samples: 4 }
    }
}

/// An adapter and the device opened on it.
pub struct Gpu {
    /// The graphics adapter (the GPU, or a software driver such as lavapipe) the device runs on.
    pub adapter: wgpu::Adapter,
    /// The logical device that owns every buffer, texture and pipeline of the renderer.
    pub device: wgpu::Device,
    /// The device's command queue, to which every frame is submitted.
    pub queue: wgpu::Queue,
}

impl Gpu {
    /// Opens a device without a display.
    pub fn new(opts: &GpuOptions) -> Result<Gpu, RenderError> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = opts.backends;
        desc.flags = wgpu::InstanceFlags::empty();
        let instance = wgpu::Instance::new(desc.with_env());
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::from_env().unwrap_or_default(),
            force_fallback_adapter: opts.software,
            compatible_surface: None,
            apply_limit_buckets: false,
        }))
        .map_err(|e| RenderError::NoAdapter(e.to_string()))?;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("spraysim-render"),
            required_features: wgpu::Features::empty(),
            required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|e| RenderError::Device(e.to_string()))?;
        Ok(Gpu { adapter, device, queue })
    }

    /// The adapter's name and backend, e.g. `llvmpipe (LLVM 15.0.6, 256 bits), Vulkan`.
    pub fn describe(&self) -> String {
        let i = self.adapter.get_info();
        format!("{}, {:?}", i.name, i.backend)
    }
}

/// The uniform block of the shader.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Globals {
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    viewport: [f32; 4],
}

/// A vertex buffer that grows as needed.
#[derive(Default)]
struct Slot {
    buffer: Option<wgpu::Buffer>,
    len: u32,
}

impl Slot {
    fn upload(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        bytes: &[u8],
        usage: wgpu::BufferUsages,
        count: usize,
    ) {
        self.len = count as u32;
        if bytes.is_empty() {
            return;
        }
        let size = bytes.len() as u64;
        if self.buffer.as_ref().is_none_or(|b| b.size() < size) {
            self.buffer = Some(device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("scene"),
                size: size.next_power_of_two().max(256),
                usage: usage | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }));
        }
        if let Some(b) = &self.buffer {
            queue.write_buffer(b, 0, bytes);
        }
    }

    fn get(&self) -> Option<(&wgpu::Buffer, u32)> {
        self.buffer.as_ref().filter(|_| self.len > 0).map(|b| (b, self.len))
    }
}

/// Pipelines and buffers that draw a [`Scene`] into a render pass of one colour format, depth
/// format and sample count.
pub struct Renderer {
    globals: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    mesh_pipeline: wgpu::RenderPipeline,
    line_pipeline: wgpu::RenderPipeline,
    point_pipeline: wgpu::RenderPipeline,
    vertices: Slot,
    indices: Slot,
    lines: Slot,
    points: Slot,
    point_size: f32,
    lighting: bool,
}

impl Renderer {
    /// A renderer for passes into `color` targets with `depth` (or no depth buffer) and
    /// `samples` samples per pixel.
    pub fn new(
        device: &wgpu::Device,
        color: wgpu::TextureFormat,
        depth: Option<wgpu::TextureFormat>,
        samples: u32,
    ) -> Renderer {
        let shader = device.create_shader_module(wgpu::include_wgsl!("scene.wgsl"));
        let globals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("globals"),
            size: std::mem::size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bgl = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &bgl,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: globals.as_entire_binding() }],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene"),
            bind_group_layouts: &[Some(&bgl)],
            immediate_size: 0,
        });
        let make = Pipelines { device, shader: &shader, layout: &layout, color, depth, samples };
        let mesh_attrs = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Unorm8x4];
        let flat_attrs = wgpu::vertex_attr_array![0 => Float32x3, 1 => Unorm8x4];
        let mesh = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<MeshVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &mesh_attrs,
        };
        let flat = |step_mode| wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<ColorVertex>() as u64,
            step_mode,
            attributes: &flat_attrs,
        };
        Renderer {
            mesh_pipeline: make.build(
                "mesh",
                ("vs_mesh", "fs_mesh"),
                mesh,
                wgpu::PrimitiveTopology::TriangleList,
            ),
            line_pipeline: make.build(
                "lines",
                ("vs_line", "fs_flat"),
                flat(wgpu::VertexStepMode::Vertex),
                wgpu::PrimitiveTopology::LineList,
            ),
            point_pipeline: make.build(
                "points",
                ("vs_point", "fs_flat"),
                flat(wgpu::VertexStepMode::Instance),
                wgpu::PrimitiveTopology::TriangleStrip,
            ),
            globals,
            bind_group,
            vertices: Slot::default(),
            indices: Slot::default(),
            lines: Slot::default(),
            points: Slot::default(),
            point_size: 3.0,
            lighting: true,
        }
    }

    /// Uploads `scene`'s geometry, reusing the buffers when they are large enough.
    pub fn upload(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene) {
        use wgpu::BufferUsages as U;
        let m = &scene.mesh;
        self.vertices.upload(device, queue, bytemuck::cast_slice(&m.vertices), U::VERTEX, m.vertices.len());
        self.indices.upload(device, queue, bytemuck::cast_slice(&m.indices), U::INDEX, m.indices.len());
        self.lines.upload(device, queue, bytemuck::cast_slice(&scene.lines), U::VERTEX, scene.lines.len());
        self.points.upload(device, queue, bytemuck::cast_slice(&scene.points), U::VERTEX, scene.points.len());
        self.point_size = scene.point_size;
        self.lighting = scene.lighting;
    }

    /// Sets the view for the next draws: `camera` over a viewport of `width × height` px,
    /// clipping at `depth` (near, far; m).
    pub fn set_view(
        &self,
        queue: &wgpu::Queue,
        camera: &Camera,
        (width, height): (u32, u32),
        depth: (f64, f64),
    ) {
        let aspect = f64::from(width.max(1)) / f64::from(height.max(1));
        let e = camera.eye.as_vec3();
        let g = Globals {
            view_proj: camera.view_proj(aspect, depth).to_cols_array_2d(),
            eye: [e.x, e.y, e.z, if self.lighting { 1.0 } else { 0.0 }],
            viewport: [width.max(1) as f32, height.max(1) as f32, self.point_size, 0.0],
        };
        queue.write_buffer(&self.globals, 0, bytemuck::bytes_of(&g));
    }

    /// Records the draws of the uploaded scene into `pass` (which it neither begins nor ends).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_bind_group(0, &self.bind_group, &[]);
        if let (Some((vb, _)), Some((ib, n))) = (self.vertices.get(), self.indices.get()) {
            pass.set_pipeline(&self.mesh_pipeline);
            pass.set_vertex_buffer(0, vb.slice(..));
            pass.set_index_buffer(ib.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..n, 0, 0..1);
        }
        if let Some((b, n)) = self.lines.get() {
            pass.set_pipeline(&self.line_pipeline);
            pass.set_vertex_buffer(0, b.slice(..));
            pass.draw(0..n, 0..1);
        }
        if let Some((b, n)) = self.points.get() {
            pass.set_pipeline(&self.point_pipeline);
            pass.set_vertex_buffer(0, b.slice(..));
            pass.draw(0..4, 0..n);
        }
    }
}

/// What every pipeline of a renderer shares.
struct Pipelines<'a> {
    device: &'a wgpu::Device,
    shader: &'a wgpu::ShaderModule,
    layout: &'a wgpu::PipelineLayout,
    color: wgpu::TextureFormat,
    depth: Option<wgpu::TextureFormat>,
    samples: u32,
}

impl Pipelines<'_> {
    fn build(
        &self,
        label: &str,
        (vs, fs): (&str, &str),
        vertex: wgpu::VertexBufferLayout<'_>,
        topology: wgpu::PrimitiveTopology,
    ) -> wgpu::RenderPipeline {
        self.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(label),
            layout: Some(self.layout),
            vertex: wgpu::VertexState {
                module: self.shader,
                entry_point: Some(vs),
                compilation_options: Default::default(),
                buffers: &[Some(vertex)],
            },
            primitive: wgpu::PrimitiveState { topology, cull_mode: None, ..Default::default() },
            depth_stencil: self.depth.map(|format| wgpu::DepthStencilState {
                format,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::LessEqual),
                stencil: wgpu::StencilState::default(),
                bias: wgpu::DepthBiasState::default(),
            }),
            multisample: wgpu::MultisampleState { count: self.samples, ..Default::default() },
            fragment: Some(wgpu::FragmentState {
                module: self.shader,
                entry_point: Some(fs),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: self.color,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        })
    }
}

/// The textures of an offscreen view.
struct Targets {
    width: u32,
    height: u32,
    color: wgpu::Texture,
    msaa: Option<wgpu::TextureView>,
    depth: wgpu::TextureView,
    readback: wgpu::Buffer,
    row_bytes: u32,
}

impl Targets {
    fn new(device: &wgpu::Device, width: u32, height: u32, samples: u32) -> Targets {
        let size = wgpu::Extent3d { width, height, depth_or_array_layers: 1 };
        let texture = |label, format, usage, sample_count| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        use wgpu::TextureUsages as T;
        let color = texture("color", COLOR_FORMAT, T::RENDER_ATTACHMENT | T::COPY_SRC, 1);
        let msaa = (samples > 1).then(|| {
            texture("color-msaa", COLOR_FORMAT, T::RENDER_ATTACHMENT, samples)
                .create_view(&Default::default())
        });
        let depth =
            texture("depth", DEPTH_FORMAT, T::RENDER_ATTACHMENT, samples).create_view(&Default::default());
        let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let row_bytes = (width * 4).div_ceil(align) * align;
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: u64::from(row_bytes) * u64::from(height),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        Targets { width, height, color, msaa, depth, readback, row_bytes }
    }
}

/// A view rendered to images, without a display.
pub struct Offscreen {
    gpu: Gpu,
    renderer: Renderer,
    targets: Targets,
    samples: u32,
}

impl Offscreen {
    /// Opens a device per `opts` and prepares images of `width × height` px.
    pub fn new(opts: &GpuOptions, width: u32, height: u32) -> Result<Offscreen, RenderError> {
        if !(1..=8192).contains(&width) || !(1..=8192).contains(&height) {
            return Err(RenderError::Settings(format!(
                "image size must be 1 to 8192 px a side, got {width} × {height}"
            )));
        }
        let gpu = Gpu::new(opts)?;
        let supported = |f: wgpu::TextureFormat| {
            gpu.adapter.get_texture_format_features(f).flags.sample_count_supported(opts.samples)
        };
        let samples = if opts.samples > 1 && supported(COLOR_FORMAT) && supported(DEPTH_FORMAT) {
            opts.samples
        } else {
            1
        };
        let renderer = Renderer::new(&gpu.device, COLOR_FORMAT, Some(DEPTH_FORMAT), samples);
        let targets = Targets::new(&gpu.device, width, height, samples);
        Ok(Offscreen { gpu, renderer, targets, samples })
    }

    /// The adapter in use, e.g. `llvmpipe (LLVM 15.0.6, 256 bits), Vulkan`.
    pub fn describe(&self) -> String {
        format!("{}, {} sample(s) per pixel", self.gpu.describe(), self.samples)
    }

    /// Image width and height, px.
    pub fn size(&self) -> (u32, u32) {
        (self.targets.width, self.targets.height)
    }

    /// Renders `scene` seen by `camera`, without legend or caption (see
    /// [`crate::overlay::annotate`]).
    pub fn render(&mut self, scene: &Scene, camera: &Camera) -> Result<image::RgbaImage, RenderError> {
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        let t = &self.targets;
        self.renderer.upload(device, queue, scene);
        self.renderer.set_view(queue, camera, (t.width, t.height), camera.depth_range(&scene.framing));
        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("view") });
        let resolved = t.color.create_view(&Default::default());
        {
            let bg = BACKGROUND.map(|c| f64::from(c) / 255.0);
            let (view, resolve_target) = match &t.msaa {
                Some(m) => (m, Some(&resolved)),
                None => (&resolved, None),
            };
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("view"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color { r: bg[0], g: bg[1], b: bg[2], a: 1.0 }),
                        store: wgpu::StoreOp::Store,
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
            self.renderer.draw(&mut pass);
        }
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &t.color,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &t.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(t.row_bytes),
                    rows_per_image: Some(t.height),
                },
            },
            wgpu::Extent3d { width: t.width, height: t.height, depth_or_array_layers: 1 },
        );
        queue.submit([encoder.finish()]);
        self.read_back()
    }

    /// Maps the readback buffer and copies the image out of it, without the row padding.
    fn read_back(&self) -> Result<image::RgbaImage, RenderError> {
        let t = &self.targets;
        let slice = t.readback.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        let err = |e: &dyn std::fmt::Display| RenderError::Readback(e.to_string());
        self.gpu
            .device
            .poll(wgpu::PollType::Wait { submission_index: None, timeout: Some(Duration::from_secs(600)) })
            .map_err(|e| err(&e))?;
        rx.recv().map_err(|e| err(&e))?.map_err(|e| err(&e))?;
        let mut pixels = Vec::with_capacity((t.width * t.height * 4) as usize);
        {
            let data = slice.get_mapped_range().map_err(|e| RenderError::Readback(format!("{e:?}")))?;
            for row in data.chunks_exact(t.row_bytes as usize) {
                pixels.extend_from_slice(&row[..(t.width * 4) as usize]);
            }
        }
        t.readback.unmap();
        image::RgbaImage::from_raw(t.width, t.height, pixels)
            .ok_or_else(|| RenderError::Readback("the image has the wrong size".into()))
    }
}

/// What [`time_frames`] measured.
#[derive(Clone, Debug)]
pub struct FrameTime {
    /// Particles drawn.
    pub particles: usize,
    /// Building the scene on the CPU, s.
    pub scene: f64,
    /// Uploading, drawing and reading the image back, s (median of the runs).
    pub draw: f64,
    /// Name and backend of the adapter the frames were drawn on.
    pub adapter: String,
}

/// Times the view of `sim` (three-quarter preset, `width × height` px, every particle drawn):
/// one untimed frame, then the median of `repeats` frames.
pub fn time_frames(
    sim: &spraysim::Simulation,
    (width, height): (u32, u32),
    repeats: usize,
) -> Result<FrameTime, RenderError> {
    use crate::scene::SceneOptions;
    let options = SceneOptions { max_particles: usize::MAX, ..SceneOptions::default() };
    let start = std::time::Instant::now();
    let scene = Scene::build(sim, &options);
    let scene_time = start.elapsed().as_secs_f64();
    let mut view = Offscreen::new(&GpuOptions::default(), width, height)?;
    let aspect = f64::from(width) / f64::from(height);
    let camera =
        Camera::preset(spraysim::scenario::ViewPreset::Iso, &scene.framing, 40f64.to_radians(), aspect);
    view.render(&scene, &camera)?;
    let mut times = Vec::new();
    for _ in 0..repeats.max(1) {
        let t = std::time::Instant::now();
        view.render(&scene, &camera)?;
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    Ok(FrameTime {
        particles: scene.points.len(),
        scene: scene_time,
        draw: times[times.len() / 2],
        adapter: view.describe(),
    })
}
