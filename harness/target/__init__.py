"""A target folder: its interface, properties, mission scripts and layer description (what the user writes)."""
