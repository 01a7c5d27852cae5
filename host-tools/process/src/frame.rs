//! Per-frame radar processing on the host with the module's `dsp` code: range cube, range
//! profile, range–Doppler map, and the azimuth of any cell.

use crate::ProcessError;
use metamoran_dsp::array::VirtualArray;
use metamoran_dsp::azimuth::azimuth_spectrum;
use metamoran_dsp::config::{RadarConfig, azimuth_bin_to_angle};
use metamoran_dsp::detect::quadratic_offset;
use metamoran_dsp::doppler::{
    DopplerOptions, doppler_column, magnitude, range_doppler_rows_keeping,
};
use metamoran_dsp::fft::{self, Exponent};
use metamoran_dsp::fixed::{CQ15, Q15};
use metamoran_dsp::range::{RangeCube, RangeProcessor};
use metamoran_dsp::units::signed_bin;
use metamoran_dsp::window::{self, WindowKind};

/// Shortest axis that gets a window; shorter ones are processed rectangular.
pub const MIN_WINDOW_LEN: usize = 8;

/// Processing choices.
#[derive(Clone, Copy, Debug)]
pub struct FrameOptions {
    /// Window over the ADC samples before the range FFT.
    pub range_window: WindowKind,
    /// Window over the loops before the Doppler FFT.
    pub doppler_window: WindowKind,
    /// Subtract the mean over loops before the Doppler FFT.
    pub remove_static: bool,
}

/// The spectra of one frame.
#[derive(Clone, Debug)]
pub struct FrameSpectra {
    /// Mean |range spectrum| over all chirps and receivers, per range bin (linear, full scale 1).
    pub range_profile: Vec<f32>,
    /// |Doppler spectrum| summed over channels: `range_bins × doppler_len`, natural FFT order.
    pub range_doppler: Vec<f32>,
    /// Range FFT length.
    pub range_bins: usize,
    /// Doppler FFT length.
    pub doppler_len: usize,
}

/// Runs `a` here and `b` on a second thread (this host's two cores), `a`'s error first. A
/// panic in `b` goes on in the caller, as it would have run there.
fn both<E: Send>(
    a: impl FnOnce() -> Result<(), E>,
    b: impl FnOnce() -> Result<(), E> + Send,
) -> Result<(), E> {
    std::thread::scope(|s| {
        let other = s.spawn(b);
        let mine = a();
        let theirs = other
            .join()
            .unwrap_or_else(|p| std::panic::resume_unwind(p));
        mine.and(theirs)
    })
}

/// Owns the buffers for processing frames of one configuration.
pub struct FrameProcessor {
    config: RadarConfig,
    options: FrameOptions,
    range_window: Vec<Q15>,
    doppler_window: Vec<Q15>,
    cube: RangeCube<Vec<CQ15>, Vec<Exponent>>,
    array: VirtualArray,
    scratch: Vec<CQ15>,
    kept: Option<KeptSpectra>,
}

/// The Doppler spectra of every (range bin, channel) of the last frame, `[bin][channel][nd]`,
/// each column's block exponent beside it: what the range–Doppler map was formed from, kept for
/// the point cloud.
struct KeptSpectra {
    columns: Vec<CQ15>,
    exponents: Vec<Exponent>,
}

/// Where the map's pass over range bins `first..` keeps each spectrum it forms: `columns` and
/// `exponents` are that part of [`KeptSpectra`] (`channels` columns of `nd` per bin).
fn keeper<'a>(
    first: usize,
    (channels, nd): (usize, usize),
    columns: &'a mut [CQ15],
    exponents: &'a mut [Exponent],
) -> impl FnMut(usize, usize, Exponent, &[CQ15]) + 'a {
    move |bin, channel, e, column| {
        let cell = (bin - first) * channels + channel;
        exponents[cell] = e;
        columns[cell * nd..(cell + 1) * nd].copy_from_slice(column);
    }
}

/// [`KeptSpectra`] as [`frame_points`](metamoran_dsp::points::frame_points) reads them.
struct KeptSource<'a> {
    kept: &'a KeptSpectra,
    channels: usize,
    nd: usize,
}

impl metamoran_dsp::points::DopplerSpectra for KeptSource<'_> {
    fn channels(&self) -> usize {
        self.channels
    }

    fn load(
        &mut self,
        bin: usize,
        out: &mut [fft::Complex32],
    ) -> Result<(), metamoran_dsp::points::PointsError> {
        let (ch, nd) = (self.channels, self.nd);
        let missing = metamoran_dsp::points::PointsError::Buffer("kept spectra");
        let exponents = self
            .kept
            .exponents
            .get(bin * ch..(bin + 1) * ch)
            .ok_or(missing)?;
        let columns = self
            .kept
            .columns
            .get(bin * ch * nd..(bin + 1) * ch * nd)
            .ok_or(missing)?;
        if nd == 0 || out.len() != ch * nd {
            return Err(metamoran_dsp::points::PointsError::Buffer("spectra"));
        }
        for ((o, column), &e) in out
            .chunks_exact_mut(nd)
            .zip(columns.chunks_exact(nd))
            .zip(exponents)
        {
            metamoran_dsp::points::spectrum_f32(e, column, o);
        }
        Ok(())
    }
}

impl FrameProcessor {
    /// Buffers for `config`.
    ///
    /// # Errors
    /// [`ProcessError`] if the configuration cannot be processed.
    pub fn new(config: &RadarConfig, options: FrameOptions) -> Result<Self, ProcessError> {
        config.validate()?;
        let array = VirtualArray::new(config)?;
        let make = |kind, len| {
            let mut w = vec![Q15::ZERO; len];
            window::fill(kind, &mut w);
            w
        };
        let (nr, nd, loops) = (
            config.range_fft_len(),
            config.doppler_fft_len(),
            config.chirps_per_tx as usize,
        );
        let rows = config.channels() * loops;
        let cube = RangeCube::new(
            vec![CQ15::default(); rows * nr],
            vec![Exponent::default(); rows],
            config.slots(),
            config.rx_count(),
            loops,
            nr,
        )?;
        Ok(Self {
            config: config.clone(),
            options,
            range_window: make(options.range_window, config.adc_samples as usize),
            doppler_window: make(options.doppler_window, loops),
            cube,
            array,
            scratch: vec![CQ15::default(); nd],
            kept: None,
        })
    }

    /// Keeps every Doppler spectrum the range–Doppler map is formed from (`range bins ×
    /// channels × Doppler length` values: 6 MB for a 192-channel imaging frame), so that
    /// [`Self::points`] reads them instead of forming those of each detected range bin again.
    /// The same points, bit for bit.
    #[must_use]
    pub fn keeping_doppler_spectra(mut self) -> Self {
        let c = &self.config;
        let cells = c.range_fft_len() * c.channels();
        self.kept = Some(KeptSpectra {
            columns: vec![CQ15::default(); cells * c.doppler_fft_len()],
            exponents: vec![Exponent::default(); cells],
        });
        self
    }

    /// The configuration.
    pub fn config(&self) -> &RadarConfig {
        &self.config
    }

    /// The virtual array.
    pub fn array(&self) -> &VirtualArray {
        &self.array
    }

    /// The window table to use, if any. Symmetric windows shorter than
    /// [`MIN_WINDOW_LEN`] are (nearly) all zero (a 2-point Hann is `[0, 0]`), so short axes
    /// stay rectangular.
    fn window_of(kind: WindowKind, table: &[Q15]) -> Option<&[Q15]> {
        (kind != WindowKind::Rectangular && table.len() >= MIN_WINDOW_LEN).then_some(table)
    }

    /// The Doppler options this processor's map and cloud use (its Doppler window), with or
    /// without static removal.
    pub fn doppler_options(&self, remove_static: bool) -> DopplerOptions<'_> {
        DopplerOptions {
            remove_static,
            window: Self::window_of(self.options.doppler_window, &self.doppler_window),
        }
    }

    /// The range cube of the last processed frame.
    pub fn cube(&self) -> &RangeCube<Vec<CQ15>, Vec<Exponent>> {
        &self.cube
    }

    /// Range-processes one frame (`[chirp][rx][sample]`) into the cube and returns its spectra.
    ///
    /// # Errors
    /// [`ProcessError`] if the frame has the wrong size.
    pub fn process(&mut self, frame: &[CQ15]) -> Result<FrameSpectra, ProcessError> {
        let c = &self.config;
        let (n, rx, nr, nd) = (
            c.adc_samples as usize,
            c.rx_count(),
            c.range_fft_len(),
            c.doppler_fft_len(),
        );
        if frame.len() != c.samples_per_frame() {
            return Err(ProcessError::FrameLength {
                got: frame.len(),
                expected: c.samples_per_frame(),
            });
        }
        let window = Self::window_of(self.options.range_window, &self.range_window);
        let processor = RangeProcessor::new(n, nr, window)?;
        // Each row is its own chirp's and receiver's: half of them on a second thread, the
        // same bits as one after the other.
        let mut rows: Vec<_> = self.cube.rows_mut().collect();
        let mid = rows.len() / 2;
        let (first, second) = rows.split_at_mut(mid);
        let fill = |part: &mut [(usize, usize, &mut [CQ15], &mut Exponent)]| {
            part.iter_mut().try_for_each(|(chirp, r, out, exp)| {
                let start = (*chirp * rx + *r) * n;
                **exp = processor.process(&frame[start..start + n], out)?;
                Ok::<(), ProcessError>(())
            })
        };
        both(|| fill(first), || fill(second))?;
        drop(rows);
        let mut range_profile = vec![0f32; nr];
        let mut rows = 0;
        for (row, exp) in self.cube.rows() {
            rows += 1;
            for (p, &z) in range_profile.iter_mut().zip(row) {
                *p += magnitude(z, exp);
            }
        }
        range_profile.iter_mut().for_each(|p| *p /= rows as f32);
        let mut range_doppler = vec![0f32; nr * nd];
        // Range bins are independent too: the upper half on a second thread.
        let mut scratch = std::mem::take(&mut self.scratch);
        let mut upper_scratch = vec![CQ15::default(); nd];
        let options = DopplerOptions {
            remove_static: self.options.remove_static,
            window: Self::window_of(self.options.doppler_window, &self.doppler_window),
        };
        let half = nr / 2;
        let (lower, upper) = range_doppler.split_at_mut(half * nd);
        let cube = &self.cube;
        // With kept spectra, each half keeps its own rows' (disjoint parts of the store).
        let ch = self.array.channels();
        let (mut lower_keep, mut upper_keep) = match self.kept.as_mut() {
            None => (None, None),
            Some(kept) => {
                let (lower_columns, upper_columns) = kept.columns.split_at_mut(half * ch * nd);
                let (lower_exps, upper_exps) = kept.exponents.split_at_mut(half * ch);
                (
                    Some(keeper(0, (ch, nd), lower_columns, lower_exps)),
                    Some(keeper(half, (ch, nd), upper_columns, upper_exps)),
                )
            }
        };
        let result = both(
            || {
                let keep =
                    |bin, c, e, z: &[CQ15]| lower_keep.as_mut().map_or((), |k| k(bin, c, e, z));
                range_doppler_rows_keeping(cube, &options, &mut scratch, 0, lower, keep)
            },
            || {
                let keep =
                    |bin, c, e, z: &[CQ15]| upper_keep.as_mut().map_or((), |k| k(bin, c, e, z));
                range_doppler_rows_keeping(cube, &options, &mut upper_scratch, half, upper, keep)
            },
        );
        self.scratch = scratch;
        result?;
        Ok(FrameSpectra {
            range_profile,
            range_doppler,
            range_bins: nr,
            doppler_len: nd,
        })
    }

    /// The Doppler spectrum (natural FFT order) and block exponent of every channel at range
    /// bin `bin` of the last frame, each computed once.
    ///
    /// # Errors
    /// [`ProcessError`] if the bin is out of range.
    pub fn doppler_spectra(
        &mut self,
        bin: usize,
        remove_static: bool,
    ) -> Result<Vec<(Exponent, Vec<CQ15>)>, ProcessError> {
        let mut scratch = std::mem::take(&mut self.scratch);
        let mut out = Vec::with_capacity(self.array.channels());
        let mut result = Ok(());
        for ch in 0..self.array.channels() {
            match doppler_column(
                &self.cube,
                ch,
                bin,
                &self.doppler_options(remove_static),
                &mut scratch,
            ) {
                Ok(e) => out.push((e, scratch.clone())),
                Err(e) => {
                    result = Err(e.into());
                    break;
                }
            }
        }
        self.scratch = scratch;
        result.map(|()| out)
    }

    /// Channel values of range bin `bin` at Doppler index `doppler` of the last frame, aligned to
    /// one exponent (index 0 without static removal is the sum over loops: the static scene).
    ///
    /// # Errors
    /// [`ProcessError`] if an index is out of range.
    pub fn channel_values(
        &mut self,
        bin: usize,
        doppler: usize,
        remove_static: bool,
    ) -> Result<(Vec<CQ15>, Exponent), ProcessError> {
        let spectra = self.doppler_spectra(bin, remove_static)?;
        let top = spectra.iter().map(|(e, _)| e.0).max().unwrap_or(0);
        let values = spectra
            .iter()
            .map(|(e, s)| {
                s.get(doppler)
                    .map(|z| z.scale_down(top - e.0))
                    .ok_or(ProcessError::DopplerIndex(doppler))
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok((values, Exponent(top)))
    }

    /// The point cloud of the last processed frame (`spectra` is what [`Self::process`]
    /// returned for it): [`metamoran_dsp::points::frame_points`] over the Doppler spectra the
    /// map's pass kept ([`Self::keeping_doppler_spectra`]) or else formed again from this
    /// processor's range cube, the farther half of the range bins on a second thread (the same
    /// points in the same order, either way).
    ///
    /// # Errors
    /// [`ProcessError`] if the buffers do not fit the configuration.
    pub fn points(
        &mut self,
        spectra: &FrameSpectra,
        geometry: &metamoran_dsp::points::ArrayGeometry,
        options: &metamoran_dsp::points::CloudOptions,
    ) -> Result<Vec<metamoran_dsp::points::RadarPoint>, ProcessError> {
        let nd = spectra.doppler_len;
        let doppler = self.doppler_options(self.options.remove_static);
        let (cube, config, kept) = (&self.cube, &self.config, self.kept.as_ref());
        let part = |bins: std::ops::Range<usize>, out: &mut Vec<_>| {
            let held = options.peaks.bins_held();
            let mut values = vec![fft::Complex32::new(0.0, 0.0); geometry.channels() * nd * held];
            let mut scratch = vec![CQ15::default(); nd];
            let (mut from_kept, mut from_cube);
            let source: &mut dyn metamoran_dsp::points::DopplerSpectra = match kept {
                Some(kept) => {
                    let channels = cube.channels();
                    from_kept = KeptSource { kept, channels, nd };
                    &mut from_kept
                }
                None => {
                    from_cube = metamoran_dsp::points::CubeSpectra {
                        cube,
                        doppler,
                        scratch: &mut scratch,
                    };
                    &mut from_cube
                }
            };
            metamoran_dsp::points::frame_points(
                source,
                config,
                geometry,
                &spectra.range_doppler,
                options,
                bins,
                &mut values,
                |p| out.push(p),
            )
            .map(drop)
            .map_err(ProcessError::from)
        };
        let half = spectra.range_bins / 2;
        let (mut near, mut far) = (Vec::new(), Vec::new());
        both(
            || part(0..half, &mut near),
            || part(half..usize::MAX, &mut far),
        )?;
        near.append(&mut far);
        Ok(near)
    }

    /// Azimuth FFT length used for this array: 4× oversampled, at least 64 points.
    pub fn azimuth_len(&self) -> usize {
        fft::padded_len((4 * self.array.span()).max(64)).unwrap_or(fft::MAX_LEN)
    }

    /// |azimuth spectrum| (natural FFT order, [`Self::azimuth_len`] points) of range bin `bin`
    /// at Doppler index `doppler` of the last frame, in full-scale units.
    ///
    /// # Errors
    /// [`ProcessError`] if an index is out of range.
    pub fn azimuth_profile(
        &mut self,
        bin: usize,
        doppler: usize,
        remove_static: bool,
    ) -> Result<Vec<f32>, ProcessError> {
        let (values, exp) = self.channel_values(bin, doppler, remove_static)?;
        let mut spec = vec![CQ15::default(); self.azimuth_len()];
        let e = azimuth_spectrum(&self.array, &values, &mut spec)?;
        let scale = Exponent(exp.0 + e.0);
        Ok(spec.iter().map(|&z| magnitude(z, scale)).collect())
    }

    /// Azimuth of the strongest direction at range bin `bin`, Doppler index `doppler` (natural
    /// FFT order; index 0 without static removal is the static scene) of the last processed
    /// frame, by a zero-padded azimuth FFT with quadratic interpolation. `None` if the peak lies
    /// outside the visible region.
    ///
    /// # Errors
    /// [`ProcessError`] if an index is out of range.
    pub fn azimuth_at(
        &mut self,
        bin: usize,
        doppler: usize,
        remove_static: bool,
    ) -> Result<Option<f32>, ProcessError> {
        let mag = self.azimuth_profile(bin, doppler, remove_static)?;
        let na = mag.len();
        let k = (0..na)
            .max_by(|&a, &b| mag[a].total_cmp(&mag[b]))
            .unwrap_or(0);
        let db = |i: usize| 20.0 * (mag[i % na].max(1e-30)).log10();
        let offset = quadratic_offset(db(k + na - 1), db(k), db(k + 1));
        let bin = signed_bin(k, na) as f32 + offset;
        Ok(azimuth_bin_to_angle(bin, na))
    }
}
