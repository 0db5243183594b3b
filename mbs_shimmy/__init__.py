"""Geometrically full multibody model of the axle in Exudyn."""
