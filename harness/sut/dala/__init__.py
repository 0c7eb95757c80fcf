"""Dala's behaviour: the pymunk world, the laser, navigation and its five modules."""
