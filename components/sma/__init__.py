"""The SMA wire of §thermal-model: the thermal model (`thermal`, `ends`, the submodels of
`submodels`), the modified Preisach hysteresis (`surface`, `preisach`) and its inverse
(`inverse`), the drift (`drift`), the SmaWire's core (`smawire`) and ports (`ports`), the reference
wire (`reference_wire`), the data sets (`datasets`, `forcfile`), reference profiles (`profiles`),
closed-form surfaces (`analytic`) and the monolithic model of §position-control (`monolithic`)."""

__all__ = ["analytic", "datasets", "drift", "ends", "forcfile", "inverse", "monolithic", "ports",
           "preisach", "profiles", "reference_wire", "smawire", "submodels", "surface", "thermal"]
