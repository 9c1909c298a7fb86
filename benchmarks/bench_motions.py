"""Strip-theory motions benchmarks (issue 16 item 7) and the KCS σ_aw side by side with SNNM and STAWAVE-2.

1. ``motions`` (heave, pitch, R_AWM) of a Wigley (41 stations, 25 strips × 12 panels) at 30 frequencies:
   value, and value + gradient of Σ R_AWM w.r.t. a beam scale, jitted and warm; compile times.
2. The design objective's motion part: ``mean_added_resistance`` (NMRI, H_s 3 m, T_p 9 s, 15 kn, head seas)
   ``.motion`` of the same Wigley, value and value + gradient, warm and compile (20 λ/L knots).
3. vmap over designs (beam scale) × 30 frequencies: time per design in a batch of ``N_DESIGNS`` (default 256),
   evaluated as one jitted program in chunks of ``CHUNK`` designs (default 32; ``jax.lax.map(..., batch_size=)``:
   a vmap over each chunk, the chunks in sequence, so memory is that of one chunk), with the process's peak RSS
   before and after the batch (``resource.getrusage``), and the same for one vmap over a single chunk.
4. KCS at Fn 0.26, head seas: σ_aw = R_AW/(ρgζ²B²/L) by NMRI (strip-theory motion part + Bf reflection), SNNM
   and STAWAVE-2 at the same λ/L.

Run: ``cd benchmarks && ../.venv/bin/python bench_motions.py [N_DESIGNS [CHUNK]]``; results in
results/motions.json.
"""

from __future__ import annotations

import resource
import sys
import time

import jax

jax.config.update("jax_enable_x64", True)

import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402
from _common import HULLS, save, timeit  # noqa: E402

from hullopt.geometry import Sections  # noqa: E402
from hullopt.models import wigley  # noqa: E402
from hullopt.waves import mean_added_resistance, method_resistance, motions, omega_from_wavelength  # noqa: E402

G, RHO = 9.80665, 1025.0


def _peak_rss_gib() -> float:
    """This process's peak resident set size so far [GiB] (Linux: ru_maxrss in KiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20


def _scaled(hull, scale):
    return Sections(x=hull.x, yz=hull.yz * jnp.stack([scale, 1.0]), lpp=hull.lpp)


def main() -> None:
    n_designs = int(sys.argv[1]) if len(sys.argv) > 1 else 256
    chunk = min(int(sys.argv[2]) if len(sys.argv) > 2 else 32, n_designs)
    hull = wigley(100.0, 10.0, 6.25, 9.0, n=41, m=41)
    omega = omega_from_wavelength(jnp.linspace(0.4, 2.5, 30) * 100.0)
    u = 0.2 * np.sqrt(G * 100.0)

    def value(scale):
        return jnp.sum(motions(_scaled(hull, scale), 6.25, u, omega).r_awm)

    # the batch first, so its peak RSS is not that of the gradients' compilation below
    rss_before = _peak_rss_gib()
    fc = jax.jit(jax.vmap(value))
    one_chunk = jnp.linspace(0.9, 1.1, chunk)
    t0 = time.perf_counter()
    jax.block_until_ready(fc(one_chunk))
    compile_chunk = time.perf_counter() - t0
    t_chunk = timeit(lambda: jax.block_until_ready(fc(one_chunk)), 3)
    rss_chunk = _peak_rss_gib()
    fv = jax.jit(lambda s: jax.lax.map(value, s, batch_size=chunk))
    scales = jnp.linspace(0.9, 1.1, n_designs)
    t0 = time.perf_counter()
    batch_values = jax.block_until_ready(fv(scales))
    first_batch = time.perf_counter() - t0
    t_batch = timeit(lambda: jax.block_until_ready(fv(scales)), 2)
    rss_batch = _peak_rss_gib()
    chunk_check = float(jnp.max(jnp.abs(batch_values[:chunk] - fc(scales[:chunk]))))
    f = jax.jit(value)
    t0 = time.perf_counter()
    jax.block_until_ready(f(1.0))
    compile_value = time.perf_counter() - t0
    t_value = timeit(lambda: jax.block_until_ready(f(1.0)), 5)
    fg = jax.jit(jax.value_and_grad(value))
    t0 = time.perf_counter()
    jax.block_until_ready(fg(1.0))
    compile_grad = time.perf_counter() - t0
    t_grad = timeit(lambda: jax.block_until_ready(fg(1.0)), 5)

    def objective(scale):
        return mean_added_resistance("nmri", _scaled(hull, scale), 6.25, 7.7, 3.0, 9.0).motion

    fo = jax.jit(objective)
    t0 = time.perf_counter()
    jax.block_until_ready(fo(1.0))
    compile_obj = time.perf_counter() - t0
    t_obj = timeit(lambda: jax.block_until_ready(fo(1.0)), 5)
    fog = jax.jit(jax.value_and_grad(objective))
    t0 = time.perf_counter()
    jax.block_until_ready(fog(1.0))
    compile_obj_grad = time.perf_counter() - t0
    t_obj_grad = timeit(lambda: jax.block_until_ready(fog(1.0)), 5)


    from hullopt.study import load_hull

    kcs = load_hull(str(HULLS / "kcs_model_closed_from_igs.stl.gz") + "?scale=31.6&lpp=230&n=61").sections
    lam = np.array([0.3, 0.5, 0.7, 0.9, 1.0, 1.1, 1.2, 1.3, 1.4, 1.6, 2.0])
    om = jnp.asarray(omega_from_wavelength(lam * 230.0))
    uk = 0.26 * np.sqrt(G * 230.0)
    scale = RHO * G * 32.2**2 / 230.0
    sigma = {}
    for method in ("nmri", "snnm", "stawave2"):
        r = jax.jit(lambda s, m=method: method_resistance(m, s, 10.8, uk, om, 0.0, kyy=0.25, kg=7.28))(kcs)
        sigma[method] = {"total": (np.asarray(r.total) / scale).round(3).tolist(),
                         "motion": (np.asarray(r.motion) / scale).round(3).tolist(),
                         "reflection": (np.asarray(r.reflection) / scale).round(3).tolist()}
    out = {
        "wigley_41_stations_30_frequencies": {
            "value_s": t_value, "value_and_grad_s": t_grad, "ratio": t_grad / t_value,
            "compile_value_s": compile_value, "compile_value_and_grad_s": compile_grad,
            "vmap_designs": n_designs, "vmap_chunk": chunk, "vmap_batch_s": t_batch,
            "vmap_per_design_s": t_batch / n_designs, "vmap_first_call_s": first_batch,
            "vmap_chunk_s": t_chunk, "vmap_chunk_per_design_s": t_chunk / chunk, "vmap_chunk_compile_s": compile_chunk,
            "peak_rss_gib_before_vmap": rss_before, "peak_rss_gib_after_one_chunk": rss_chunk,
            "peak_rss_gib_after_batch": rss_batch, "batch_vs_chunk_max_abs_diff_n": chunk_check,
        },
        "objective_motion_part_wigley_hs3_tp9_15kn": {
            "value_s": t_obj, "value_and_grad_s": t_obj_grad, "ratio": t_obj_grad / t_obj,
            "compile_value_s": compile_obj, "compile_value_and_grad_s": compile_obj_grad,
            "value_n": float(fo(1.0)),
        },
        "kcs_fn026_head_seas_sigma_aw": {"lambda_over_l": lam.tolist(), **sigma},
    }
    print(save("motions", out))
    print(out)


if __name__ == "__main__":
    main()
