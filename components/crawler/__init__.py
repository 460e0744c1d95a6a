"""The friction-switching crawler of §crawler: body (`body`), friction blocks (`friction`), the
gait (`gait`), the ideal inputs (`inputs`), the monolithic reference (`monolithic`) and the FMUs
(`slaves`)."""

__all__ = ["body", "friction", "gait", "inputs", "monolithic"]
