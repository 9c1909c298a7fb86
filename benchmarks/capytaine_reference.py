"""Zero-speed heave and pitch RAOs of a Wigley hull in head seas by Capytaine (3D BEM), the reference for
hullopt's strip theory (tests/test_motions.py reads the stored result).

The mesh is made here from the Wigley formula y = (B/2)(1 − (2ξ/L)²)(1 − (z/T)²), independently of hullopt,
as a port half (quadrilaterals, cosine-spaced along x) and its mirror image; an internal lid
removes the irregular frequencies. Degrees of freedom: heave and pitch only (as strip theory), rotation
about the centre of gravity at midship on the waterline (KG = T), mass ρ∇ of the mesh, pitch radius of
gyration 0.25 L. Deep water, ρ = 1025 kg/m³, g = 9.80665 m/s², waves from the bow (Capytaine direction π).

Run:  .venv/bin/python benchmarks/capytaine_reference.py [--nx 60 --nz 14] [--out tests/data/wigley_capytaine_raos.json]
(needs ``pip install capytaine``; a few minutes on two cores).
"""

from __future__ import annotations

import argparse
import datetime
import json
from pathlib import Path

import numpy as np

L, B, T = 100.0, 10.0, 6.25  # L/B 10, B/T 1.6
RHO, G = 1025.0, 9.80665
KYY = 0.25
LAMBDA_OVER_L = [0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.1, 1.2, 1.3, 1.4, 1.5, 1.75, 2.0, 2.5, 3.0]


def wigley_half_mesh(nx: int, nz: int):
    import capytaine as cpt

    u = 0.5 * (1.0 - np.cos(np.linspace(0.0, np.pi, nx + 1)))
    xi = (u - 0.5) * L  # from midship
    z = np.linspace(-T, 0.0, nz + 1)
    X, Z = np.meshgrid(xi, z, indexing="ij")
    Y = 0.5 * B * (1.0 - (2.0 * X / L) ** 2) * (1.0 - (Z / T) ** 2)
    verts = np.stack([X + 0.5 * L, Y, Z], axis=-1).reshape(-1, 3)
    idx = np.arange((nx + 1) * (nz + 1)).reshape(nx + 1, nz + 1)
    faces = np.stack([idx[:-1, :-1], idx[:-1, 1:], idx[1:, 1:], idx[1:, :-1]], axis=-1).reshape(-1, 4)
    return cpt.Mesh(vertices=verts, faces=faces, name="wigley_half")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nx", type=int, default=60)
    ap.add_argument("--nz", type=int, default=14)
    ap.add_argument("--out", default=str(Path(__file__).resolve().parents[1] / "tests/data/wigley_capytaine_raos.json"))
    args = ap.parse_args()

    import capytaine as cpt
    import xarray as xr

    half = wigley_half_mesh(args.nx, args.nz)
    if np.mean(half.faces_normals[:, 1]) < 0:  # normals into the fluid (+y on the port half)
        raise SystemExit("port half mesh has inward normals")
    v = half.vertices.copy()
    v[:, 1] *= -1.0
    mesh = half.join_meshes(cpt.Mesh(vertices=v, faces=np.asarray(half.faces)[:, ::-1], name="wigley_starboard"))
    lid = mesh.generate_lid(z=-0.01 * T, faces_max_radius=0.5 * L / args.nx)
    cog = np.array([0.5 * L, 0.0, 0.0])
    body = cpt.FloatingBody(mesh=mesh, lid_mesh=lid, dofs=cpt.rigid_body_dofs(only=["Heave", "Pitch"], rotation_center=cog),
                            center_of_mass=cog)
    volume = float(body.mesh.volume)
    mass = RHO * volume
    body.mass = mass
    stiff = body.compute_hydrostatic_stiffness(rho=RHO, g=G)
    inertia = xr.DataArray(np.diag([mass, mass * (KYY * L) ** 2]),
                           dims=["influenced_dof", "radiating_dof"],
                           coords={"influenced_dof": ["Heave", "Pitch"], "radiating_dof": ["Heave", "Pitch"]})
    lam = np.asarray(LAMBDA_OVER_L) * L
    k = 2.0 * np.pi / lam
    omega = np.sqrt(G * k)
    test_matrix = xr.Dataset(coords={"omega": omega, "wave_direction": [np.pi], "radiating_dof": ["Heave", "Pitch"],
                                     "water_depth": [np.inf], "rho": [RHO], "g": [G]})
    ds = cpt.BEMSolver().fill_dataset(test_matrix, body)
    ds["inertia_matrix"] = inertia
    ds["hydrostatic_stiffness"] = stiff
    rao = cpt.post_pro.rao(ds)
    rao = rao.sel(omega=omega, method="nearest")  # the dataset sorts ω ascending: back to the λ/L order
    heave = np.abs(rao.sel(radiating_dof="Heave").values).ravel()
    pitch = np.abs(rao.sel(radiating_dof="Pitch").values).ravel() / k
    out = {
        "description": "Wigley hull y=(B/2)(1-(2x/L)^2)(1-(z/T)^2), zero speed, head seas, heave |z|/zeta and pitch "
                       "|theta|/(k zeta); heave+pitch dofs about the CG at midship on the waterline (KG=T), mass rho*V, "
                       "kyy=0.25L; deep water; rho 1025, g 9.80665. Made by benchmarks/capytaine_reference.py.",
        "L": L, "B": B, "T": T, "kyy_over_L": KYY, "kg": T,
        "capytaine_version": cpt.__version__,
        "date": datetime.date.today().isoformat(),
        "mesh": {"nx": args.nx, "nz": args.nz, "faces_half_hull": int(half.nb_faces), "lid_faces": int(lid.nb_faces),
                 "volume": volume},
        "lambda_over_l": list(map(float, LAMBDA_OVER_L)),
        "omega": omega.tolist(),
        "heave": heave.tolist(),
        "pitch": pitch.tolist(),
    }
    Path(args.out).write_text(json.dumps(out, indent=1) + "\n")
    for row in zip(LAMBDA_OVER_L, heave, pitch):
        print("λ/L %.2f  heave %.4f  pitch %.4f" % row)


if __name__ == "__main__":
    main()
