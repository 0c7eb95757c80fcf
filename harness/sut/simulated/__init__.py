"""The simulated functional layer: an event kernel, the module framework, the layer a layer.toml describes."""
