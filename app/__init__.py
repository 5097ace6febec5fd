"""The Quasirigid explorer: a viser web app that draws the spinning body and integrates the chosen
model live, one simulation per browser tab. Run it with ``python -m app``. It uses only what
``physics`` exports; physics never imports it."""
