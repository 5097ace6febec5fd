"""The Quasirigid explorer: a viser web app that draws the spinning body and integrates the chosen
model live, one simulation per browser tab. Run it with ``python -m app``. It uses only what
``physics`` exports; physics never imports it."""


def show(scenario=None, **options):
    """Serve the explorer and show it inline in a Jupyter notebook; returns a handle whose ``stop()`` ends it
    (app.serve.notebook.show: its options). Imported on call, so ``import app`` stays light."""
    from .serve.notebook import show as _show

    return _show(scenario, **options)
