//! Adapter choice and device creation, headless (no window, no surface). Vulkan everywhere
//! (every desktop GPU driver on Linux and Windows, and Mesa's lavapipe, a CPU Vulkan
//! rasteriser, what CI has); Metal on Apple platforms, DX12 on Windows, GL/GLES through EGL
//! on Linux and Android, each compiled only there ([`backends`]).

use std::fmt;
use std::sync::{Arc, Mutex};

use anyhow::{bail, Context, Result};

/// What a result row records about the adapter.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AdapterLine {
    pub name: String,
    pub backend: String,
    pub driver: String,
    pub device_type: String,
}

impl AdapterLine {
    pub fn new(info: &wgpu::AdapterInfo) -> Self {
        let driver = match (info.driver.is_empty(), info.driver_info.is_empty()) {
            (false, false) => format!("{} {}", info.driver, info.driver_info),
            (false, true) => info.driver.clone(),
            _ => info.driver_info.clone(),
        };
        AdapterLine {
            name: info.name.clone(),
            backend: format!("{:?}", info.backend),
            driver,
            device_type: format!("{:?}", info.device_type),
        }
    }
}

impl fmt::Display for AdapterLine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({}, {}, driver {})", self.name, self.backend, self.device_type, self.driver)
    }
}

/// An open device.
pub struct Gpu {
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub line: AdapterLine,
    /// `Features::TIMESTAMP_QUERY` was available and enabled.
    pub timestamps: bool,
    /// Errors wgpu reported outside an error scope (its default handler panics); [`Gpu::wait`]
    /// returns them as an error.
    uncaptured: Arc<Mutex<Vec<String>>>,
}

/// Mesa's desktop GL renders to RGBA32F (float colour buffers are core since GL 3.0) but
/// lists neither GL_ARB_color_buffer_float nor GL_EXT_color_buffer_float, the strings wgpu
/// looks for before it allows the runner's float targets. Mesa reads
/// `MESA_EXTENSION_OVERRIDE` when EGL starts a context: this adds the first to it, once,
/// before any instance exists (the variable left as it is when it already names it, or
/// disables it with `-`). Other drivers ignore the variable.
pub const MESA_GL_OVERRIDE: &str = "+GL_ARB_color_buffer_float";

/// The value `MESA_EXTENSION_OVERRIDE` should have given its current one.
pub fn mesa_override(current: Option<&str>) -> Option<String> {
    let name = &MESA_GL_OVERRIDE[1..];
    match current {
        None => Some(MESA_GL_OVERRIDE.to_string()),
        Some(value) if value.split_whitespace().any(|w| w.trim_start_matches(['+', '-']) == name) => None,
        Some(value) if value.trim().is_empty() => Some(MESA_GL_OVERRIDE.to_string()),
        Some(value) => Some(format!("{value} {MESA_GL_OVERRIDE}")),
    }
}

fn instance() -> wgpu::Instance {
    static MESA: std::sync::Once = std::sync::Once::new();
    if cfg!(any(target_os = "linux", target_os = "android")) {
        MESA.call_once(|| {
            let current = std::env::var("MESA_EXTENSION_OVERRIDE").ok();
            if let Some(value) = mesa_override(current.as_deref()) {
                std::env::set_var("MESA_EXTENSION_OVERRIDE", value);
            }
        });
    }
    wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env())
}

/// Every adapter the instance sees.
pub fn adapters() -> Vec<AdapterLine> {
    let instance = instance();
    pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all())).iter().map(|a| AdapterLine::new(&a.get_info())).collect()
}

/// Real GPUs first, CPU rasterisers last.
fn preference(device_type: wgpu::DeviceType) -> u8 {
    match device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Other => 3,
        wgpu::DeviceType::Cpu => 4,
    }
}

/// The backends this build has, by the name `--backend` takes.
pub fn backends() -> Vec<(&'static str, wgpu::Backend)> {
    let mut compiled = vec![("vulkan", wgpu::Backend::Vulkan)];
    if cfg!(any(target_os = "macos", target_os = "ios")) {
        compiled.push(("metal", wgpu::Backend::Metal));
    }
    if cfg!(windows) {
        compiled.push(("dx12", wgpu::Backend::Dx12));
    }
    if cfg!(any(target_os = "linux", target_os = "android")) {
        compiled.push(("gl", wgpu::Backend::Gl));
    }
    compiled
}

/// Vulkan before the others where two backends reach one device.
fn backend_preference(backend: wgpu::Backend) -> u8 {
    match backend {
        wgpu::Backend::Vulkan => 0,
        wgpu::Backend::Metal | wgpu::Backend::Dx12 => 1,
        _ => 2,
    }
}

/// Open the adapter whose name contains `wanted` (case-insensitive) on `backend` (a name
/// of [`backends`]), else the most capable one (discrete > integrated > virtual > other >
/// CPU; Vulkan first among equals).
pub fn open(wanted: Option<&str>, backend: Option<&str>) -> Result<Gpu> {
    let instance = instance();
    let mut adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
    if adapters.is_empty() {
        let names: Vec<&str> = backends().into_iter().map(|(name, _)| name).collect();
        bail!(
            "no GPU adapter found (backends built: {}). Without a GPU, install a software Vulkan driver: \
             `apt-get install mesa-vulkan-drivers` (lavapipe)",
            names.join(", ")
        );
    }
    if let Some(name) = backend {
        let compiled = backends();
        let Some((_, wanted_backend)) = compiled.iter().find(|(n, _)| n.eq_ignore_ascii_case(name)) else {
            let names: Vec<&str> = compiled.iter().map(|(n, _)| *n).collect();
            bail!("backend {name:?} is not built here; built: {}", names.join(", "));
        };
        let all: Vec<String> = adapters.iter().map(|a| AdapterLine::new(&a.get_info()).to_string()).collect();
        adapters.retain(|a| a.get_info().backend == *wanted_backend);
        if adapters.is_empty() {
            bail!("no adapter on the {name} backend; adapters: {}", all.join("; "));
        }
    }
    let names: Vec<String> = adapters.iter().map(|a| AdapterLine::new(&a.get_info()).to_string()).collect();
    if let Some(wanted) = wanted {
        let needle = wanted.to_lowercase();
        adapters.retain(|a| a.get_info().name.to_lowercase().contains(&needle));
        if adapters.is_empty() {
            bail!("no adapter name contains {wanted:?}; adapters: {}", names.join("; "));
        }
    }
    adapters.sort_by_key(|a| (preference(a.get_info().device_type), backend_preference(a.get_info().backend)));
    let adapter = adapters.swap_remove(0);
    let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
    let required_features = if timestamps { wgpu::Features::TIMESTAMP_QUERY } else { wgpu::Features::empty() };
    let descriptor = wgpu::DeviceDescriptor {
        label: Some("nklut"),
        required_features,
        required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
        ..Default::default()
    };
    let line = AdapterLine::new(&adapter.get_info());
    let (device, queue) = pollster::block_on(adapter.request_device(&descriptor)).with_context(|| format!("opening a device on {line}"))?;
    let uncaptured = Arc::new(Mutex::new(Vec::new()));
    let sink = uncaptured.clone();
    device.on_uncaptured_error(Arc::new(move |error: wgpu::Error| {
        sink.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).push(error.to_string());
    }));
    Ok(Gpu { adapter, device, queue, line, timestamps, uncaptured })
}

impl Gpu {
    /// Block until all submitted work has finished; an error wgpu reported since the last
    /// wait (a validation error of any call, an out-of-memory) is returned here.
    pub fn wait(&self) -> Result<()> {
        self.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| anyhow::anyhow!("waiting for the GPU: {e}"))?;
        self.take_errors()
    }

    /// The errors wgpu reported outside an error scope since the last call, as one error.
    pub fn take_errors(&self) -> Result<()> {
        let errors = std::mem::take(&mut *self.uncaptured.lock().unwrap_or_else(|poisoned| poisoned.into_inner()));
        if !errors.is_empty() {
            anyhow::bail!("wgpu reported {} error(s): {}", errors.len(), errors.join("; "));
        }
        Ok(())
    }

    /// Map `buffer` for reading, wait, and copy its bytes out.
    pub fn read_buffer(&self, buffer: &wgpu::Buffer) -> Result<Vec<u8>> {
        let (sender, receiver) = std::sync::mpsc::channel();
        buffer.map_async(wgpu::MapMode::Read, .., move |result| {
            let _ = sender.send(result);
        });
        self.wait()?;
        receiver.recv().context("mapping a readback buffer")?.map_err(|e| anyhow::anyhow!("mapping a readback buffer: {e}"))?;
        let bytes = buffer.get_mapped_range(..).map_err(|e| anyhow::anyhow!("reading a mapped buffer: {e:?}"))?.to_vec();
        buffer.unmap();
        Ok(bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_mesa_override_is_added_once_and_a_user_s_choice_kept() {
        assert_eq!(mesa_override(None).as_deref(), Some("+GL_ARB_color_buffer_float"));
        assert_eq!(mesa_override(Some("")).as_deref(), Some("+GL_ARB_color_buffer_float"));
        assert_eq!(mesa_override(Some("+GL_EXT_foo")).as_deref(), Some("+GL_EXT_foo +GL_ARB_color_buffer_float"));
        assert_eq!(mesa_override(Some("+GL_ARB_color_buffer_float")), None);
        assert_eq!(mesa_override(Some("-GL_ARB_color_buffer_float")), None);
    }
}
