"""The SMA wire of SPEC.md section 2: modified Preisach hysteresis, its inverse, the thermal model."""
