"""Table 5 of Saleh 2017: the 39 workable planetary designs and their safety factors.

Columns: number, centre distance [mm], module [mm], sun, planet, ring teeth, ratio, SF_C2,5
(contact sun/planet), SF_C5,1 (contact planet/ring), min(SF_B)_r (bending at the root) and
min(SF_B)_f (the paper's "bending at the flank"). The paper's safety factors are stress ratios
greater than one for a working design, though its eqs. 36-37 are printed upside down.
"""

from __future__ import annotations

#: (#, a_mm, m_mm, sun, planet, ring, i, SF_C25, SF_C51, SF_B_root, SF_B_flank)
TABLE_5 = (
    (1, 420, 5, 53, 115, 283, 6.34, 1.58, 1.66, 0.54, 1.28),
    (2, 420, 5, 54, 114, 282, 6.22, 1.58, 1.66, 0.55, 1.30),
    (3, 420, 5, 55, 113, 281, 6.11, 1.58, 1.66, 0.56, 1.32),
    (4, 480, 5, 61, 131, 323, 6.30, 1.59, 1.66, 0.62, 1.47),
    (5, 480, 5, 62, 130, 322, 6.19, 1.59, 1.66, 0.63, 1.49),
    (6, 480, 5, 63, 129, 321, 6.10, 1.59, 1.66, 0.64, 1.51),
    (7, 540, 5, 68, 148, 364, 6.35, 1.60, 1.66, 0.69, 1.65),
    (8, 540, 5, 69, 147, 363, 6.26, 1.60, 1.66, 0.70, 1.66),
    (9, 540, 5, 70, 146, 362, 6.17, 1.60, 1.66, 0.71, 1.68),
    (10, 540, 5, 71, 145, 361, 6.09, 1.60, 1.66, 0.72, 1.70),
    (11, 600, 5, 76, 164, 404, 6.32, 1.61, 1.66, 0.77, 1.84),
    (12, 600, 5, 77, 163, 403, 6.23, 1.61, 1.66, 0.78, 1.85),
    (13, 600, 5, 78, 162, 402, 6.15, 1.61, 1.66, 0.79, 1.87),
    (14, 600, 5, 79, 161, 401, 6.08, 1.61, 1.66, 0.80, 1.89),
    (15, 540, 6, 57, 123, 303, 6.32, 1.59, 1.66, 0.83, 1.65),
    (16, 540, 6, 58, 122, 302, 6.21, 1.59, 1.66, 0.84, 1.67),
    (17, 540, 6, 59, 121, 301, 6.10, 1.59, 1.66, 0.86, 1.69),
    (18, 420, 7, 38, 82, 202, 6.32, 1.55, 1.66, 0.75, 1.27),
    (19, 420, 7, 39, 81, 201, 6.15, 1.56, 1.66, 0.77, 1.30),
    (20, 420, 8, 33, 72, 177, 6.36, 1.54, 1.66, 0.85, 1.26),
    (21, 420, 8, 34, 71, 176, 6.18, 1.54, 1.66, 0.87, 1.29),
    (22, 480, 8, 38, 82, 202, 6.32, 1.55, 1.66, 0.98, 1.45),
    (23, 480, 8, 39, 81, 201, 6.15, 1.56, 1.66, 1.00, 1.48),
    (24, 540, 8, 43, 92, 227, 6.28, 1.57, 1.66, 1.10, 1.64),
    (25, 540, 8, 44, 91, 226, 6.14, 1.57, 1.66, 1.13, 1.67),
    (26, 600, 8, 47, 103, 253, 6.38, 1.58, 1.66, 1.21, 1.80),
    (27, 600, 8, 48, 102, 252, 6.25, 1.58, 1.66, 1.23, 1.84),
    (28, 600, 8, 49, 101, 251, 6.12, 1.58, 1.66, 1.25, 1.87),
    (29, 540, 9, 38, 82, 202, 6.32, 1.56, 1.66, 1.23, 1.63),
    (30, 540, 9, 39, 81, 201, 6.15, 1.56, 1.66, 1.26, 1.67),
    (31, 420, 10, 27, 57, 141, 6.22, 1.52, 1.65, 1.07, 1.27),
    (32, 480, 10, 31, 65, 161, 6.19, 1.53, 1.65, 1.23, 1.46),
    (33, 540, 10, 34, 74, 182, 6.35, 1.54, 1.66, 1.36, 1.62),
    (34, 540, 10, 35, 73, 181, 6.17, 1.55, 1.66, 1.39, 1.65),
    (35, 600, 10, 38, 82, 202, 6.32, 1.56, 1.66, 1.51, 1.81),
    (36, 600, 10, 39, 81, 201, 6.15, 1.56, 1.66, 1.55, 1.85),
    (37, 540, 12, 29, 61, 151, 6.21, 1.53, 1.65, 1.65, 1.63),
    (38, 540, 15, 24, 48, 120, 6.00, 1.50, 1.65, 2.10, 1.66),
    (39, 540, 15, 23, 49, 121, 6.26, 1.50, 1.65, 2.02, 1.60),
)


def comparison(rows: list[dict]) -> list[dict]:
    """Our AGMA safety factors beside Table 5's, matched by design number and teeth.

    Each entry: number, teeth, the paper's four factors and ours (contact sun/planet, contact
    planet/ring, smallest bending) with relative differences (ours/paper − 1).
    """
    ours = {int(r["number"]): r for r in rows}
    out: list[dict[str, object]] = []
    for n, a, m, sun, planet, ring, _i, c25, c51, b_root, b_flank in TABLE_5:
        row = ours.get(n)
        if row is None or (int(row["sun"]), int(row["planet"]), int(row["ring"])) != (
            sun,
            planet,
            ring,
        ):
            out.append({"number": n, "missing": True})
            continue
        sf_c25 = float(row["agma_SF_contact_sun_planet"])
        sf_c51 = float(row["agma_SF_contact_planet_ring"])
        sf_b = float(row["agma_SF_bending_min"])
        out.append(
            {
                "number": n,
                "design": f"{a}/{m}/{sun}/{planet}/{ring}",
                "paper_SF_C25": c25,
                "paper_SF_C51": c51,
                "paper_SF_B_root": b_root,
                "paper_SF_B_flank": b_flank,
                "SF_C25": sf_c25,
                "SF_C51": sf_c51,
                "SF_B": sf_b,
                "missing": False,
                "diff_C25": sf_c25 / c25 - 1.0,
                "diff_C51": sf_c51 / c51 - 1.0,
                "diff_B_root": sf_b / b_root - 1.0,
                "diff_C25_vs_flank": sf_c25 / b_flank - 1.0,
            }
        )
    return out
