"""WAV output: sample rate and length read back, pitch and level as asked, no aliasing, CLI and renderer.

Cost: about 3 s (one tiny asperity run, one belt run, a few spectrogram plots).
"""

import numpy as np
import pytest
from scipy.io import wavfile

import asperity2d as a
from asperity2d import SceneError
from asperity2d.belt import presets, simulate_chain
from asperity2d.cli import main
from asperity2d.renderers import render
from asperity2d.renderers.sound import write_wav

T = np.linspace(0.0, 20.0, 40001)  # 20 s at 2 kHz


def audio_peak_hz(data, rate):
    spec = np.abs(np.fft.rfft(data * np.hanning(data.size)))
    return np.fft.rfftfreq(data.size, 1 / rate)[np.argmax(spec)]


def test_wav_reads_back_with_rate_length_pitch_and_level(tmp_path):
    y = np.sin(2 * np.pi * 2.0 * T)
    snd = write_wav((T, y), tmp_path / "tone.wav", time_scale=220.0, sample_rate=22_050, level_db=-6.0,
                    min_seconds=0.0)  # the run once: its length is the mapping's
    rate, data = wavfile.read(snd.path)
    assert rate == 22_050 and data.dtype == np.int16
    # 20 s of simulation heard 220 times faster: 20/220 s, plus the sample at t = 0
    assert data.size == snd.samples == int(np.floor(20.0 / 220.0 * 22_050)) + 1
    assert snd.duration == pytest.approx(20.0 / 220.0)
    assert audio_peak_hz(data, rate) == pytest.approx(440.0, abs=rate / data.size)  # one FFT bin
    assert np.max(np.abs(data)) == pytest.approx(32767 * 10 ** (-6 / 20), abs=1)  # peak at -6 dBFS
    assert snd.level_db == pytest.approx(-6.0)
    assert snd.spectrogram.read_bytes()[:4] == b"\x89PNG"
    assert [p.name for p in tmp_path.iterdir() if p.name.endswith(".tmp")] == []


def test_default_time_scale_puts_the_dominant_frequency_at_the_target(tmp_path):
    snd = write_wav((T, np.sin(2 * np.pi * 1.5 * T)), tmp_path / "a.wav", target_hz=300.0, spectrogram=False,
                    min_seconds=0.0)  # 0.1 s played once: a loop's turns would widen the one-bin peak
    rate, data = wavfile.read(snd.path)
    assert snd.dominant_hz == pytest.approx(1.5, rel=1e-3)
    assert audio_peak_hz(data, rate) == pytest.approx(300.0, rel=0.01)


def test_rms_normalisation(tmp_path):
    y = np.sin(2 * np.pi * 2.0 * T)
    snd = write_wav((T, y), tmp_path / "r.wav", time_scale=50.0, level_db=-20.0, normalize="rms",
                    spectrogram=False)
    _, data = wavfile.read(snd.path)
    rms_db = 20 * np.log10(np.sqrt(np.mean((data / 32767.0) ** 2)))
    assert rms_db == pytest.approx(-20.0, abs=0.05)  # the 10 ms fades take a little out


def test_components_above_the_wav_nyquist_are_filtered_not_aliased(tmp_path):
    # 2 Hz heard at 440 Hz; 70 Hz would be 15.4 kHz above the 8 kHz Nyquist of a 16 kHz WAV:
    # unfiltered, it would fold back to 16 - 15.4 = 0.6 kHz
    y = np.sin(2 * np.pi * 2.0 * T) + np.sin(2 * np.pi * 70.0 * T)
    snd = write_wav((T, y), tmp_path / "f.wav", time_scale=220.0, sample_rate=16_000, spectrogram=False,
                    min_seconds=0.0)  # played once: the turns of a loop spread the spectrum by themselves
    rate, data = wavfile.read(snd.path)
    spec = np.abs(np.fft.rfft(data * np.hanning(data.size)))
    f = np.fft.rfftfreq(data.size, 1 / rate)
    alias = spec[np.abs(f - 600.0) < 50].max()
    assert alias < 1e-3 * spec.max()


def test_render_chooses_wav_for_both_models(tmp_path):
    belt = simulate_chain(**presets.preset("table2-3dof", t_end=30.0, n_samples=3001))
    path = render(belt, tmp_path / "belt.wav", signal="v", mass=2)
    rate, data = wavfile.read(path)
    assert rate == 44_100 and data.size > 100
    run = a.simulate(a.make_scene(track="fixed", lower_count=4, upper_count=2))
    run.save(tmp_path / "run.npz")
    assert main(["render", str(tmp_path / "run.npz"), "-o", str(tmp_path / "run.wav")]) == 0
    rate, data = wavfile.read(tmp_path / "run.wav")
    assert rate == 44_100 and data.size > 100
    assert (tmp_path / "run.spectrogram.png").exists()


def test_bad_input_names_the_parameter(tmp_path):
    with pytest.raises(SceneError, match="`path`"):
        write_wav((T, np.sin(T)), tmp_path / "x.mp3")
    with pytest.raises(SceneError, match="constant"):
        write_wav((T, np.ones_like(T)), tmp_path / "x.wav", time_scale=10.0)
    with pytest.raises(SceneError, match="`time_scale`"):
        write_wav((T, np.sin(T)), tmp_path / "x.wav", time_scale=1e-3)  # 20 000 s of sound
    with pytest.raises(SceneError, match="`level_db`"):
        write_wav((T, np.sin(T)), tmp_path / "x.wav", level_db=3.0)


def test_a_belt_run_heard_at_440_hz_lasts_at_least_a_second(tmp_path):
    """The table 2 chain rings at ~0.7 Hz: heard at 440 Hz its 10 s last 16 ms, a click. The
    written WAV (read back with the standard library's ``wave``) must last at least a second,
    looped back and forth, and keep the pitch: the loop reverses time, which keeps the spectrum."""
    import wave

    out = tmp_path / "run.wav"
    assert main(["belt", "--preset", "table2-3dof", "-o", str(out)]) == 0
    with wave.open(str(out)) as w:
        frames, rate = w.getnframes(), w.getframerate()
        data = np.frombuffer(w.readframes(frames), dtype=np.int16)
    assert frames / rate >= 1.0
    # the loop keeps the pitch: the dominant 0.7 Hz is heard at 440 Hz (within 5 %, the signal is
    # a ring-down with harmonics, not a pure tone)
    assert audio_peak_hz(data, rate) == pytest.approx(440.0, rel=0.05)
    once = write_wav(simulate_chain(**presets.preset("table2-3dof")), tmp_path / "once.wav", min_seconds=0.0,
                     spectrogram=False)
    assert once.samples < 0.1 * rate  # played once it is the click it used to be


def test_min_seconds_is_checked(tmp_path):
    with pytest.raises(SceneError, match="`min_seconds`"):
        write_wav((T, np.sin(T)), tmp_path / "x.wav", time_scale=10.0, min_seconds=-1.0)
