//! The GPU device of the GPU tests: the adapter `NKLUT_GPU_ADAPTER` names on the backend
//! asked for (else `NKLUT_GPU_BACKEND`'s, else the most capable). No adapter is a failure
//! naming what to install, unless `NKLUT_SKIP_GPU_TESTS=1`, which skips with a message.

use std::sync::{Mutex, MutexGuard, OnceLock};

use nklut::gpu::{self, Gpu};

fn opened(backend: Option<&str>) -> Result<Gpu, String> {
    let from_env = std::env::var("NKLUT_GPU_BACKEND").ok();
    gpu::open(std::env::var("NKLUT_GPU_ADAPTER").ok().as_deref(), backend.or(from_env.as_deref())).map_err(|e| format!("{e:#}"))
}

/// `None` (skipped, with a message) where NKLUT_SKIP_GPU_TESTS=1; else a panic naming
/// `error` and what to install.
fn missing<T>(error: &str) -> Option<T> {
    if std::env::var("NKLUT_SKIP_GPU_TESTS").as_deref() == Ok("1") {
        eprintln!("GPU test skipped (NKLUT_SKIP_GPU_TESTS=1): {error}");
        return None;
    }
    panic!(
        "no GPU adapter for the GPU tests: {error}\n\
         Install a software Vulkan driver (Debian: apt-get install mesa-vulkan-drivers; scripts/test-deps also installs Mesa's EGL for the GL backend) \
         or set NKLUT_SKIP_GPU_TESTS=1 to skip."
    )
}

/// A device of its own on `backend` (`None`: the environment's choice).
pub fn open(backend: Option<&str>) -> Option<Gpu> {
    opened(backend).map_or_else(|error| missing(&error), Some)
}

/// One device for the whole test binary; tests take turns (2 cores, a CPU rasteriser).
pub fn shared() -> Option<MutexGuard<'static, Gpu>> {
    static GPU: OnceLock<Result<Mutex<Gpu>, String>> = OnceLock::new();
    match GPU.get_or_init(|| opened(None).map(Mutex::new)) {
        Ok(gpu) => {
            let guard = gpu.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
            eprintln!("adapter: {}", guard.line);
            Some(guard)
        }
        Err(error) => missing(error),
    }
}
