"""The host: command line, configuration files, result files, reports and plots."""
