"""The planar 5-bar leg with the offset foot (seeds 000 and 003)."""
