"""Pusher-slider simulators for comcore (filled in by the simulators issue)."""
