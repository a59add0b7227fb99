"""Reference solutions and experimental data the validation compares against."""
