"""duhamel's tests, laid out like the package (tests/project/test_tests_layout.py checks it).

One folder per package of python/duhamel (``engine`` for ``_engine``), ``system`` for its
top-level modules (``system.py``, ``modal.py``, ``runs.py``, ...), ``examples`` for the scripts
of examples/, ``robustness`` for the robustness contract over the whole public API, and
``project`` for repo-wide checks. Every folder is a package (``tests.rotor.test_rotor``), so a
test imports another by its full name. The shared helpers (``_models``, ``_hinged``, ...) are in
``_support``, which pytest puts on ``sys.path`` (``pythonpath`` in pyproject.toml).
"""
