"""The friction-switching crawler of SPEC.md section 1: body, friction blocks, ideal inputs."""
