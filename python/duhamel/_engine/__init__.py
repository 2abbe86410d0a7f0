"""The machinery behind :func:`duhamel.solve`: the route choice (:mod:`.plan`), the run with
its progress, interruption and failures (:mod:`.run`), and the one way from modal
coordinates to the physical response (:mod:`.output`); the core's typed inputs
(:mod:`.dispatch`), the first-order modes (:mod:`.coupled`), the undamped modes
(:mod:`.eigen`), the direct integrators (:mod:`.direct`), the argument checks
(:mod:`.validate`), the old spellings of the previous release (:mod:`.spellings`) and the
protocol the model's modules see one another through (:mod:`.protocols`)."""
