"""One tab's engine, headless: the scenario and its live run, the requests the GUI queued and the actions
that apply them, the clock, the buffers and history the plots read, the frame a tab publishes (as plain
numbers: geometry, sphere, trail; the parts are the systems' figures), compare mode's second run, the
background workers, and the explorer's vocabulary (sliders in ``controls``, presets, meshes, uploads, ``words``).

Plain Python over ``physics``'s public names: nothing here imports viser (a contract in pyproject.toml), so
the tests drive an engine without a browser. Every other package of app sits above this one.
"""
