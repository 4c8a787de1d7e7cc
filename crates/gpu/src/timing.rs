//! Timing of fullscreen passes: GPU timestamp queries at the start and end of the pass where
//! the adapter has `Features::TIMESTAMP_QUERY`, else wall time around submit-and-wait.
//! Optionally the study's subtraction: an expensive pass alone, then the same pass with the
//! measured shader drawn on top; the difference is the measured shader's cost.

use std::time::Instant;

use anyhow::Result;

use super::context::Gpu;
use super::render::Target;
use nklut_effects::scene::TimingSettings;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Timer {
    /// GPU timestamps written at the beginning and end of the render pass.
    Timestamp,
    /// CPU wall time from submit until the device is idle.
    Wall,
}

impl Timer {
    pub fn name(self) -> &'static str {
        match self {
            Timer::Timestamp => "timestamp",
            Timer::Wall => "wall",
        }
    }
}

pub use nklut_pipeline::stats::median_and_iqr;

/// One draw of a fullscreen pass: a pipeline and its bind group.
pub type Draw<'a> = (&'a wgpu::RenderPipeline, &'a wgpu::BindGroup);

/// Times one pass at a time.
pub struct Stopwatch {
    queries: Option<(wgpu::QuerySet, wgpu::Buffer, wgpu::Buffer)>,
    period_ns: f64,
    pub passes: u64,
}

impl Stopwatch {
    pub fn new(gpu: &Gpu) -> anyhow::Result<Self> {
        let queries = gpu.timestamps.then(|| -> anyhow::Result<_> {
            let set = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass time"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            });
            let resolve = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps"),
                size: 16,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            Ok((set, resolve, super::render::readback_buffer(gpu, 16)?))
        });
        Ok(Stopwatch { queries: queries.transpose()?, period_ns: gpu.queue.get_timestamp_period() as f64, passes: 0 })
    }

    pub fn timer(&self) -> Timer {
        if self.queries.is_some() {
            Timer::Timestamp
        } else {
            Timer::Wall
        }
    }

    /// Draw `draws` (3-vertex fullscreen triangles) in one pass into `target`; milliseconds.
    pub fn time(&mut self, gpu: &Gpu, target: &Target, draws: &[Draw<'_>]) -> Result<f64> {
        self.time_pass(gpu, |encoder, timestamps| {
            let writes = timestamps.map(|set| wgpu::RenderPassTimestampWrites {
                query_set: set,
                beginning_of_pass_write_index: Some(0),
                end_of_pass_write_index: Some(1),
            });
            let mut pass = target.begin(encoder, writes);
            for (pipeline, bind_group) in draws {
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, *bind_group, &[]);
                pass.draw(0..3, 0..1);
            }
        })
    }

    /// Time the one pass `record` encodes; it writes that pass's start and end into
    /// timestamp queries 0 and 1 of the set it is handed (none without timestamp queries:
    /// then wall time). Milliseconds.
    pub fn time_pass(&mut self, gpu: &Gpu, record: impl FnOnce(&mut wgpu::CommandEncoder, Option<&wgpu::QuerySet>)) -> Result<f64> {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        record(&mut encoder, self.queries.as_ref().map(|(set, _, _)| set));
        if let Some((set, resolve, read)) = &self.queries {
            encoder.resolve_query_set(set, 0..2, resolve, 0);
            encoder.copy_buffer_to_buffer(resolve, 0, read, 0, 16);
        }
        let start = Instant::now();
        gpu.queue.submit([encoder.finish()]);
        gpu.wait()?;
        let wall_ms = start.elapsed().as_secs_f64() * 1e3;
        self.passes += 1;
        match &self.queries {
            Some((_, _, read)) => {
                let bytes = gpu.read_buffer(read)?;
                let ticks: &[u64] = bytemuck::cast_slice(&bytes);
                Ok(ticks[1].wrapping_sub(ticks[0]) as f64 * self.period_ns / 1e6)
            }
            None => Ok(wall_ms),
        }
    }

    /// One sample of `measured`: its pass time, or with `burner` time(burner, then measured
    /// on top) − time(burner alone).
    pub fn sample(&mut self, gpu: &Gpu, target: &Target, measured: Draw<'_>, burner: Option<Draw<'_>>) -> Result<f64> {
        Ok(match burner {
            Some(burner) => {
                let alone = self.time(gpu, target, &[burner])?;
                self.time(gpu, target, &[burner, measured])? - alone
            }
            None => self.time(gpu, target, &[measured])?,
        })
    }

    /// Samples of every configuration, interleaved: `settings.warmup` untimed rounds, then
    /// `settings.repeats` rounds that each take one sample of every configuration in turn,
    /// so a change in background load over the run affects all configurations alike.
    pub fn measure_interleaved(
        &mut self,
        gpu: &Gpu,
        target: &Target,
        measured: &[Draw<'_>],
        burner: Option<&wgpu::RenderPipeline>,
        settings: &TimingSettings,
    ) -> Result<Vec<Vec<f64>>> {
        let mut samples = vec![Vec::with_capacity(settings.repeats as usize); measured.len()];
        for round in 0..settings.warmup + settings.repeats {
            for (draw, out) in measured.iter().zip(&mut samples) {
                let sample = self.sample(gpu, target, *draw, burner.map(|b| (b, draw.1)))?;
                if round >= settings.warmup {
                    out.push(sample);
                }
            }
        }
        Ok(samples)
    }
}
