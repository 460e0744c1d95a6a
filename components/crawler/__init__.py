"""The friction-switching crawler of §crawler: body, friction blocks, ideal inputs."""
