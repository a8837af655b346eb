"""The sound of a run: a WAV file of one signal, and its spectrogram beside it.

Friction vibrations are rarely audible as simulated: the multi-DOF belt thesis' belt chains
ring at ~0.5-1 Hz, the asperity slider's stick-slip at MHz. A **time-scale
factor** s maps simulated time t to playback time t/s, so every simulated
frequency f is heard at s·f; by default s puts the signal's dominant
frequency at ``target_hz`` (440 Hz). The signal is resampled to the WAV rate
(linear interpolation; above the WAV's Nyquist frequency it is first
low-passed with an 8th-order zero-phase Butterworth filter, so nothing
aliases), its mean removed, faded in and out over 10 ms (no clicks), and
**normalised** to ``level_db`` dB full scale, by its peak (default) or by its
RMS (never clipping: the gain is capped at the peak). Written as 16-bit PCM
with ``scipy.io.wavfile``, atomically.

A sound must last long enough to be heard: a run heard shorter than
``min_seconds`` (1 s) is **looped back and forth** -- played forwards, then
backwards, then forwards ... until it lasts ``min_seconds`` -- before the
fades. Time reversal keeps every frequency and its level, and the signal is
continuous at each turn (no jump, so no click); the pitch stays where the time
scale puts it. A 10 s belt run whose dominant 0.7 Hz is heard at 440 Hz lasts
16 ms once, and is looped 63 times. ``min_seconds=0`` writes the run once.

``render(result, "run.wav")`` and ``asperity2d render run.npz -o run.wav``
call :func:`write_wav` with its defaults; the spectrogram goes to
``run.spectrogram.png``.
"""

from __future__ import annotations

import io
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._io import atomic_write
from ..errors import SceneError

FADE_S = 0.010  # playback seconds of fade-in and fade-out


@dataclass(frozen=True)
class Sound:
    """What was written: ``path``, ``spectrogram`` (or None), ``sample_rate`` (Hz), ``samples``,
    ``duration`` (playback s, loops included), ``time_scale`` (playback frequency / simulated frequency),
    ``passes`` (how many times the run is played, alternately forwards and backwards: 1 unless it was
    shorter than ``min_seconds``),
    ``dominant_hz`` (simulated), ``gain`` (full scale per signal unit), ``level_db`` reached
    (peak or RMS, dBFS), ``signal``."""

    path: Path
    spectrogram: Path | None
    sample_rate: int
    samples: int
    duration: float
    time_scale: float
    passes: int
    dominant_hz: float
    gain: float
    level_db: float
    signal: str

    def to_dict(self) -> dict:
        return {k: (str(v) if isinstance(v, Path) else v) for k, v in self.__dict__.items()}


def write_wav(source, path: str | os.PathLike, *, signal: str = "acceleration", mass: int = 0,
              time_scale: float | None = None, target_hz: float = 440.0, sample_rate: int = 44_100,
              level_db: float = -1.0, normalize: str = "peak", spectrogram: bool = True,
              max_seconds: float = 600.0, min_seconds: float = 1.0) -> Sound:
    """Write ``signal`` of ``source`` (a Result, a BeltResult, or a ``(t, y)`` pair in SI) to ``path`` (.wav).

    See the module docstring. ``mass`` picks the belt mass (0-based).
    ``max_seconds`` bounds the playback length (a SceneError names
    ``time_scale`` if it would be longer); a run heard shorter than ``min_seconds``
    (s, default 1) is looped back and forth until it lasts that long.

    Examples
    --------
    Ten seconds of a 0.7 Hz ring heard at 440 Hz last 16 ms: looped back and forth to a second.

    >>> import numpy as np
    >>> t = np.linspace(0.0, 10.0, 2001)
    >>> snd = write_wav((t, np.sin(2 * np.pi * 0.7 * t)), "ring.wav", spectrogram=False)
    >>> snd.passes > 1, snd.duration >= 1.0
    (True, True)
    """
    from scipy import signal as sps
    from scipy.io import wavfile

    from ..dynamics.signals import check_series, resample
    from ..dynamics.spectrum import spectrum

    path = Path(path)
    if path.suffix.lower() != ".wav":
        raise SceneError(f"`path` must end in .wav, got {str(path)!r}")
    if isinstance(source, tuple):
        t, y = check_series(*source)
        name = "series"
    else:
        from ..dynamics.signals import signal as pick

        t, y = pick(source, signal, mass=mass)
        name = signal
    rate_ok = isinstance(sample_rate, (int, np.integer)) and not isinstance(sample_rate, bool)
    if not rate_ok or not 8000 <= sample_rate <= 192_000:
        raise SceneError(f"`sample_rate` must be an integer from 8000 to 192000 Hz, got {sample_rate!r}")
    if normalize not in ("peak", "rms"):
        raise SceneError(f"`normalize` must be 'peak' or 'rms', got {normalize!r}")
    if not np.isfinite(level_db) or level_db > 0:
        raise SceneError(f"`level_db` must be <= 0 dBFS, got {level_db!r}")
    tu, yu = resample(t, y)
    if np.ptp(yu) == 0:
        raise SceneError(f"`signal` {name!r} is constant: there is nothing to hear")
    dominant = spectrum(tu, yu).dominant if tu.size >= 16 else float("nan")
    if time_scale is None:
        if not np.isfinite(target_hz) or target_hz <= 0:
            raise SceneError(f"`target_hz` must be > 0, got {target_hz!r}")
        if not dominant > 0:
            why = (f"the run has {tu.size} samples, too few to find its dominant frequency (16 at "
                   "least): record a longer run" if tu.size < 16 else "the signal has no dominant frequency")
            raise SceneError(f"`time_scale` must be given: {why} (or give `time_scale`, playback "
                             "frequency over simulated frequency)")
        time_scale = target_hz / dominant
    if not np.isfinite(time_scale) or time_scale <= 0:
        raise SceneError(f"`time_scale` must be > 0, got {time_scale!r}")
    duration = (tu[-1] - tu[0]) / time_scale
    if not (np.isfinite(min_seconds) and 0 <= min_seconds <= max_seconds):
        raise SceneError(f"`min_seconds` must be within [0, max_seconds = {max_seconds:g}] s, got {min_seconds!r}")
    if duration > max_seconds:
        raise SceneError(f"`time_scale` {time_scale:.6g} makes {duration:.4g} s of sound (more than "
                         f"max_seconds = {max_seconds:g}); raise it or shorten the run")
    count = int(np.floor(duration * sample_rate)) + 1
    if count < 2:
        raise SceneError(f"`time_scale` {time_scale:.6g} makes less than two samples of sound")
    src_rate = 1.0 / (tu[1] - tu[0])  # simulated Hz
    cutoff = 0.45 * sample_rate / time_scale  # simulated Hz heard just below the WAV's Nyquist
    if src_rate > 2 * cutoff and yu.size > 60:
        sos = sps.butter(8, cutoff, fs=src_rate, output="sos")
        yu = sps.sosfiltfilt(sos, yu)
    audio = np.interp(tu[0] + np.arange(count) * (time_scale / sample_rate), tu, yu)  # playback -> simulated t
    passes = 1
    if count < min_seconds * sample_rate:
        # back and forth: each turn repeats its end sample once, so the signal never jumps
        passes = int(np.ceil(min_seconds * sample_rate / count))
        audio = np.concatenate([audio if k % 2 == 0 else audio[::-1] for k in range(passes)])
        count = audio.size
    audio -= audio.mean()
    fade = min(int(FADE_S * sample_rate), count // 4)
    if fade > 0:
        ramp = 0.5 - 0.5 * np.cos(np.linspace(0.0, np.pi, fade))
        audio[:fade] *= ramp
        audio[-fade:] *= ramp[::-1]
    peak = float(np.max(np.abs(audio)))
    if peak == 0:
        raise SceneError(f"`signal` {name!r} has no variation left to hear after removing its mean")
    target = 10.0 ** (level_db / 20.0)
    gain = target / peak
    if normalize == "rms":
        gain = min(target / float(np.sqrt(np.mean(audio**2))), 1.0 / peak)
    pcm = np.round(np.clip(audio * gain, -1.0, 1.0) * 32767).astype(np.int16)
    reached = peak * gain if normalize == "peak" else float(np.sqrt(np.mean((audio * gain) ** 2)))

    def write(fh):
        buf = io.BytesIO()
        wavfile.write(buf, sample_rate, pcm)
        fh.write(buf.getvalue())

    atomic_write(path, write)
    picture = None
    if spectrogram:
        top = 12 * dominant if dominant > 0 else None  # the first dozen harmonics
        picture = plot_spectrogram(tu, yu, path.with_name(path.stem + ".spectrogram.png"),
                                   time_scale=time_scale, f_max=top, title=f"{name}: heard x{time_scale:.4g}")
    return Sound(path, picture, int(sample_rate), int(count), float(passes * duration), float(time_scale),
                 passes, float(dominant), float(gain), float(20 * np.log10(reached)), name)


def plot_spectrogram(t, y, path: str | os.PathLike, *, time_scale: float = 1.0, f_max: float | None = None,
                     title: str = "", dpi: int = 120) -> Path:
    """Spectrogram (dB) of a uniformly sampled ``y(t)``: simulated time and frequency on the axes,
    the frequency heard (x ``time_scale``) on the right-hand axis; shown up to ``f_max`` (simulated Hz,
    default Nyquist) and never above 20 kHz heard."""
    from scipy import signal as sps

    from .plots import figure, save

    fs = 1.0 / (t[1] - t[0])
    nperseg = int(min(max(64, t.size // 48), t.size))
    f, tt, S = sps.spectrogram(y - np.mean(y), fs=fs, nperseg=nperseg, noverlap=nperseg * 3 // 4)
    fig, axes = figure(1, width=7.5, height=3.6)
    ax = axes[0]
    db = 10 * np.log10(np.maximum(S, S.max() * 1e-12))
    im = ax.pcolormesh(t[0] + tt, f, db, shading="auto", cmap="magma", vmin=db.max() - 80, vmax=db.max())
    fig.colorbar(im, ax=ax, label="power (dB)", pad=0.12)
    ax.set_xlabel("simulated time (s)")
    ax.set_ylabel("simulated frequency (Hz)")
    top = min(fs / 2, 20_000.0 / time_scale, f_max if f_max else np.inf)
    ax.set_ylim(0, top)
    heard = ax.secondary_yaxis("right", functions=(lambda v: v * time_scale, lambda v: v / time_scale))
    heard.set_ylabel("heard (Hz)")
    ax.set_title(title, fontsize=9)
    return save(fig, path, dpi)
