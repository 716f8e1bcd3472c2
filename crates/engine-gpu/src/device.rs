//! The adapter and device the kernels run on.

use crate::GpuError;

/// Which adapter to run on.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct GpuOptions {
    /// Only a software adapter (Mesa's lavapipe): slow, but on every machine, for tests.
    pub software: bool,
    /// The most layer epochs one call of the flight stage takes: 0 (the default)
    /// [`EPOCHS_PER_CALL`], fewer where a layer stage falls due or the GPU's memory is full; 1 a
    /// call per epoch, with the layers settled on the CPU between two (slower: for comparisons).
    pub max_epochs_per_call: u64,
}

/// The most layer epochs a call takes by default: 0.64 s of simulated time at the default
/// epoch of 5 ms. Enough that the cost of a call (a submission and a wait, some milliseconds)
/// is spread thin, few enough that a run without layer stages stays responsive to an interrupt
/// and schedules its births a call at a time, not all at once.
pub const EPOCHS_PER_CALL: u64 = 128;

/// An adapter and the device opened on it.
#[derive(Debug)]
pub struct Gpu {
    /// The adapter: a GPU, or a software driver such as lavapipe.
    pub adapter: wgpu::Adapter,
    /// The device that owns the buffers and pipelines.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
}

impl Gpu {
    /// Opens a device on the first Vulkan adapter (the fastest, where there are several), or on
    /// a software one where `options` asks; `WGPU_ADAPTER_NAME` picks one by name. The device
    /// takes the adapter's own largest storage binding and buffer (the default limits
    /// elsewhere), and its timestamps between kernels where it writes them inside passes.
    pub fn open(options: &GpuOptions) -> Result<Gpu, GpuError> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = wgpu::Backends::VULKAN;
        desc.flags = wgpu::InstanceFlags::empty();
        let instance = wgpu::Instance::new(desc.with_env());
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: options.software,
            compatible_surface: None,
            apply_limit_buckets: false,
        }))
        .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        // The adapter's own binding and buffer sizes (a GPU's are often larger than the
        // default 128 MiB, so that more scenes share a dispatch), and the timestamps between
        // kernels where it writes them, for the profile.
        let offered = adapter.limits();
        let required_limits = wgpu::Limits {
            max_storage_buffer_binding_size: offered.max_storage_buffer_binding_size,
            max_buffer_size: offered.max_buffer_size,
            ..wgpu::Limits::default()
        };
        let required_features = adapter.features() & crate::timing::TIMESTAMPS;
        let required_features = if required_features == crate::timing::TIMESTAMPS {
            required_features
        } else {
            wgpu::Features::empty()
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("spraysim-gpu"),
            required_features,
            required_limits,
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|e| GpuError::Device(e.to_string()))?;
        Ok(Gpu { adapter, device, queue })
    }

    /// The most bytes one storage binding holds on this device, a multiple of 16 (the limit may
    /// be 2 GiB − 1 bytes, the most wgpu gives a binding on Vulkan, and a binding's size is a
    /// multiple of 4).
    pub fn binding_bytes(&self) -> u64 {
        self.device.limits().max_storage_buffer_binding_size & !15
    }

    /// The adapter's name, driver and backend, e.g. `llvmpipe (LLVM 15.0.6, 256 bits), Mesa
    /// 22.3.6, Vulkan`.
    pub fn describe(&self) -> String {
        let i = self.adapter.get_info();
        format!("{}, {} {}, {:?}", i.name, i.driver, i.driver_info, i.backend)
    }
}
