"""The SMA wire of §thermal-model: modified Preisach hysteresis, its inverse, the thermal model."""
