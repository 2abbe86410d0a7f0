"""The machinery behind :func:`duhamel.solve`: the route choice (:mod:`.plan`), the run with
its progress, interruption and failures (:mod:`.run`), and the one way from modal
coordinates to the physical response (:mod:`.output`)."""
