//! The kernels of the flight stage (`flight.wgsl`, then `births.wgsl`), built once per device:
//! their pipelines and the layouts of the storage they bind, and the order in which a dispatch
//! records them (`restore`, `born`, per epoch `fly`, `census`, `settle` and `census` again, and
//! `gather`).

use crate::GpuError;
use crate::device::Gpu;
use crate::pack::{self, ROW_GROUPS, WORKGROUP};
use crate::timing::{Kernel, Stamps};

/// The kernels' source: the flight, then the births, which use its bindings and helpers.
const SOURCE: &str = concat!(include_str!("flight.wgsl"), include_str!("births.wgsl"));

/// The kernels, built once per device.
#[derive(Debug)]
pub(crate) struct Kernels {
    layout: wgpu::BindGroupLayout,
    /// `census`'s group: the parameters, scene, counters and plan, and the size of the
    /// dispatches over the listed cells, which it writes and `settle` and `gather` read as
    /// their size (a buffer that no group of theirs may hold).
    census_layout: wgpu::BindGroupLayout,
    fly: wgpu::ComputePipeline,
    born: wgpu::ComputePipeline,
    restore: wgpu::ComputePipeline,
    settle: wgpu::ComputePipeline,
    census: wgpu::ComputePipeline,
    gather: wgpu::ComputePipeline,
}

impl Kernels {
    /// Builds the kernels on `gpu`; a kernel the driver cannot build is an error.
    pub fn build(gpu: &Gpu) -> Result<Kernels, GpuError> {
        let device = &gpu.device;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("flight"),
            source: wgpu::ShaderSource::Wgsl(SOURCE.into()),
        });
        let entry = |binding: u32, read_only: bool| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let params = wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                // Each epoch's parameters at their own offset.
                has_dynamic_offset: true,
                min_binding_size: Some(PARAMS_BYTES),
            },
            count: None,
        };
        let mut entries = vec![params];
        // Particles, scene (read only), layers, counters, cells, listed, plan, wear.
        entries.extend((1..=8).map(|b| entry(b, b == 2)));
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("flight"),
            entries: &entries,
        });
        let census_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("census"),
            entries: &[params, entry(2, true), entry(4, false), entry(7, false), entry(9, false)],
        });
        let pipeline = |entry: &str, layout: &wgpu::BindGroupLayout| {
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(entry),
                bind_group_layouts: &[Some(layout)],
                immediate_size: 0,
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                cache: None,
            })
        };
        let (fly, restore, settle) =
            (pipeline("fly", &layout), pipeline("restore", &layout), pipeline("settle", &layout));
        let (census, gather, born) =
            (pipeline("census", &census_layout), pipeline("gather", &layout), pipeline("born", &layout));
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Device(format!("the flight kernels do not build: {e}")));
        }
        Ok(Kernels { layout, census_layout, fly, born, restore, settle, census, gather })
    }
}

impl Kernels {
    /// The groups of a dispatch's storage: `buffers` in binding order (the parameters, then
    /// particles, scene, layers, counters, cells, listed, plan, wear, and the size of the
    /// dispatches over the listed cells).
    pub fn groups(&self, gpu: &Gpu, buffers: [&wgpu::Buffer; 10]) -> Groups {
        let entry = |k: usize| wgpu::BindGroupEntry {
            binding: k as u32,
            // The parameters: one epoch's, at the offset each dispatch gives.
            resource: if k == 0 {
                wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: buffers[0],
                    offset: 0,
                    size: Some(PARAMS_BYTES),
                })
            } else {
                buffers[k].as_entire_binding()
            },
        };
        let group = |layout: &wgpu::BindGroupLayout, bindings: &[usize]| {
            let entries: Vec<wgpu::BindGroupEntry<'_>> = bindings.iter().map(|&k| entry(k)).collect();
            gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout,
                entries: &entries,
            })
        };
        Groups {
            main: group(&self.layout, &[0, 1, 2, 3, 4, 5, 6, 7, 8]),
            census: group(&self.census_layout, &[0, 2, 4, 7, 9]),
        }
    }
}

/// A dispatch's storage bound for its kernels: `main` for all but `census`, which has a group
/// of its own (see `Kernels::census_layout`).
#[derive(Debug)]
pub(crate) struct Groups {
    main: wgpu::BindGroup,
    census: wgpu::BindGroup,
}

/// Records the kernels of a dispatch of `epochs` epochs (their parameters `stride` bytes
/// apart) over `slots` particle slots and `cells` cells, bound as `bind` (`census` in a group
/// of its own), and a timestamp after each kernel where `stamps` is given. `settle` and
/// `gather` cover the cells listed, in dispatches of the size `census` writes into `listed`.
pub(crate) fn record(
    encoder: &mut wgpu::CommandEncoder,
    kernels: &Kernels,
    (bind, listed): (&Groups, &wgpu::Buffer),
    (stride, epochs): (u64, usize),
    (slots, cells): (u32, u32),
    mut stamps: Option<&mut Stamps>,
) {
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
    if let Some(s) = stamps.as_deref_mut() {
        s.start(&mut pass);
    }
    // A kernel with the parameters at `offset`, over `size` workgroups (None: as many as
    // `census` counted for the listed cells).
    let mut run =
        |pass: &mut wgpu::ComputePass<'_>, kernel: Kernel, size: Option<(u32, u32)>, offset: u32| {
            let (pipeline, group) = match kernel {
                Kernel::Restore => (&kernels.restore, &bind.main),
                Kernel::Born => (&kernels.born, &bind.main),
                Kernel::Fly => (&kernels.fly, &bind.main),
                Kernel::Census => (&kernels.census, &bind.census),
                Kernel::Settle => (&kernels.settle, &bind.main),
                Kernel::Gather => (&kernels.gather, &bind.main),
            };
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, group, &[offset]);
            match size {
                Some((x, y)) => pass.dispatch_workgroups(x, y, 1),
                None => pass.dispatch_workgroups_indirect(listed, 0),
            }
            if let Some(s) = stamps.as_deref_mut() {
                s.after(pass, kernel);
            }
        };
    let particles = Some(groups(slots));
    run(&mut pass, Kernel::Restore, Some(groups(cells + 1)), 0);
    run(&mut pass, Kernel::Born, particles, 0);
    let mut offset = 0;
    for e in 0..epochs {
        offset = (e as u64 * stride) as u32;
        run(&mut pass, Kernel::Fly, particles, offset);
        run(&mut pass, Kernel::Census, Some((1, 1)), offset);
        // After every epoch: between two, for the next one; after the last, for
        // `read_settled_layers` (the next call starts from the layers it is handed).
        run(&mut pass, Kernel::Settle, None, offset);
        run(&mut pass, Kernel::Census, Some((1, 1)), offset);
    }
    run(&mut pass, Kernel::Gather, None, offset);
}

/// Bytes between two epochs' parameters: the adapter's alignment of uniform offsets.
pub(crate) fn params_stride(gpu: &Gpu) -> u64 {
    let align = u64::from(gpu.device.limits().min_uniform_buffer_offset_alignment);
    PARAMS_BYTES.get().next_multiple_of(align.max(1))
}

/// Bytes of one epoch's parameters.
pub(crate) const PARAMS_BYTES: wgpu::BufferSize =
    match wgpu::BufferSize::new(std::mem::size_of::<pack::Params>() as u64) {
        Some(n) => n,
        None => panic!("the parameters take bytes"),
    };

/// Workgroups (across, rows) covering `n` invocations.
pub(crate) fn groups(n: u32) -> (u32, u32) {
    let g = n.div_ceil(WORKGROUP).max(1);
    (g.min(ROW_GROUPS), g.div_ceil(ROW_GROUPS))
}
