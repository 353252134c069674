"""LACQUER: the coated material the exports are checked on, a rough blue dielectric under a glossy
clear coat, written as `slicecap fit` writes a fitted material (docs/material-fit.md, "The JSON"),
so that `slicecap generate TRUTH.json` tabulates it. Its coat weight fits in the room Mitsuba's
blend leaves (1 - 0.3 - 0.04), so the snippet need not reduce it. One definition for the
consumers' coat check (coat_consumers.py) and the export tests
(python/tests/test_material_export.py)."""

LACQUER = {
    "format": "slicecap-material", "format_version": 1, "model": "ggx+coat",
    "metrics": {"delta_e": 0.0},
    "parameters": {name: {"value": value} for name, value in {
        "diffuse_albedo": [0.05, 0.1, 0.3], "specular_f0": [0.04, 0.04, 0.04],
        "specular_f90": 1.0, "alpha_tangent": 0.4, "alpha_bitangent": 0.4, "tangent_deg": 0.0,
        "coat_weight": 0.6, "coat_alpha": 0.08}.items()},
}
