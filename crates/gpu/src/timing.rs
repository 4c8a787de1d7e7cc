//! Timing of fullscreen passes: GPU timestamp queries at the start and end of the pass where
//! the adapter has `Features::TIMESTAMP_QUERY`, else wall time around submit-and-wait.
//! Optionally the study's subtraction: an expensive pass alone, then the same pass with the
//! measured shader drawn on top; the difference is the measured shader's cost. The F-only
//! passes are sampled by the rules of [`super::sampling`] through [`FresnelClock`].

use std::time::Instant;

use anyhow::Result;

use super::context::Gpu;
use super::render::{Target, ViewUniform};
use super::sampling::{PassClock, RawSample};

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
    epoch: Instant,
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
        Ok(Stopwatch {
            queries: queries.transpose()?,
            period_ns: gpu.queue.get_timestamp_period() as f64,
            epoch: Instant::now(),
            passes: 0,
        })
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
        self.time_pass(gpu, |encoder, timestamps| record_draws(encoder, target, timestamps, draws))
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

    /// Time the one pass `record` encodes as raw readings (ns): its start and end
    /// timestamps, or the wall clock around submit-and-wait. `lead` encodes passes before
    /// it in the same submit, untimed (the throwaway pass).
    pub fn raw_pass(
        &mut self,
        gpu: &Gpu,
        lead: impl FnOnce(&mut wgpu::CommandEncoder),
        record: impl FnOnce(&mut wgpu::CommandEncoder, Option<&wgpu::QuerySet>),
    ) -> Result<RawSample> {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        lead(&mut encoder);
        record(&mut encoder, self.queries.as_ref().map(|(set, _, _)| set));
        if let Some((set, resolve, read)) = &self.queries {
            encoder.resolve_query_set(set, 0..2, resolve, 0);
            encoder.copy_buffer_to_buffer(resolve, 0, read, 0, 16);
        }
        let start = self.epoch.elapsed().as_nanos() as u64;
        gpu.queue.submit([encoder.finish()]);
        gpu.wait()?;
        let end = self.epoch.elapsed().as_nanos() as u64;
        self.passes += 1;
        match &self.queries {
            Some((_, _, read)) => {
                let bytes = gpu.read_buffer(read)?;
                let ticks: &[u64] = bytemuck::cast_slice(&bytes);
                let ns = |t: u64| (t as f64 * self.period_ns) as u64;
                Ok(RawSample { start_ns: ns(ticks[0]), end_ns: ns(ticks[0]) + ns(ticks[1].wrapping_sub(ticks[0])) })
            }
            None => Ok(RawSample { start_ns: start, end_ns: end }),
        }
    }

    /// The timer's nominal tick (ns): the timestamp period, or 1 for the wall clock.
    pub fn tick_ns(&self) -> f64 {
        if self.queries.is_some() {
            self.period_ns.max(1.0)
        } else {
            1.0
        }
    }
}

/// The F-only passes as a [`PassClock`]: each sample one submit that clears `target` in an
/// untimed throwaway pass, then draws the pair's pipeline (with `subtract`: the burner
/// alone, then the burner and the pair on top, in two such submits; the sample the
/// difference) into it with `evaluations` per pixel, written into each material's `View`
/// (`viewport.z`) before the pass.
pub struct FresnelClock<'a> {
    pub gpu: &'a Gpu,
    pub target: &'a Target,
    pub stopwatch: &'a mut Stopwatch,
    /// Per pair: its draw and its material's view buffer.
    pub draws: Vec<(Draw<'a>, &'a wgpu::Buffer)>,
    pub burner: Option<&'a wgpu::RenderPipeline>,
    pub resolution: [u32; 2],
    /// The amplification last written into every view.
    pub written: Option<u32>,
}

impl FresnelClock<'_> {
    fn write_evaluations(&mut self, evaluations: u32) {
        if self.written == Some(evaluations) {
            return;
        }
        let [width, height] = self.resolution;
        let view = ViewUniform::fullscreen_amplified(width, height, evaluations);
        for (_, buffer) in &self.draws {
            self.gpu.queue.write_buffer(buffer, 0, bytemuck::bytes_of(&view));
        }
        self.written = Some(evaluations);
    }

    /// Back to one evaluation per pixel (what a ramp readback expects).
    pub fn reset(&mut self) {
        self.write_evaluations(1);
    }

    fn one(&mut self, draws: &[Draw<'_>]) -> Result<RawSample> {
        let target = self.target;
        self.stopwatch.raw_pass(
            self.gpu,
            |encoder| drop(target.begin(encoder, None)),
            |encoder, timestamps| record_draws(encoder, target, timestamps, draws),
        )
    }
}

impl PassClock for FresnelClock<'_> {
    fn pass(&mut self, pair: usize, evaluations: u32) -> Result<RawSample> {
        self.write_evaluations(evaluations);
        let (measured, _) = self.draws[pair];
        match self.burner {
            Some(burner) => {
                let alone = self.one(&[(burner, measured.1)])?;
                let both = self.one(&[(burner, measured.1), measured])?;
                let difference = both.end_ns.saturating_sub(both.start_ns).saturating_sub(alone.end_ns.saturating_sub(alone.start_ns));
                Ok(RawSample { start_ns: both.start_ns, end_ns: both.start_ns + difference })
            }
            None => self.one(&[measured]),
        }
    }

    fn tick_ns(&self) -> f64 {
        self.stopwatch.tick_ns()
    }

    /// With the wall clock: the median round trip of five empty submits.
    fn floor_ms(&mut self) -> Result<f64> {
        if self.stopwatch.timer() == Timer::Timestamp {
            return Ok(0.0);
        }
        let mut trips = Vec::new();
        for _ in 0..5 {
            let start = Instant::now();
            self.gpu.queue.submit([self.gpu.device.create_command_encoder(&Default::default()).finish()]);
            self.gpu.wait()?;
            trips.push(start.elapsed().as_secs_f64() * 1e3);
        }
        Ok(median_and_iqr(&trips).0)
    }
}

/// Record `draws` (3-vertex fullscreen triangles) in one render pass into `target`, with
/// the pass's beginning and end timestamps written to `timestamps` where the adapter has them.
fn record_draws(encoder: &mut wgpu::CommandEncoder, target: &Target, timestamps: Option<&wgpu::QuerySet>, draws: &[Draw<'_>]) {
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
}
