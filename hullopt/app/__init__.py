"""The app layer: hull specs, config files, the CLI, reports, plots. Nothing below imports it."""
