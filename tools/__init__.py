"""Build-time tools of the repository, run from its root (`python -m tools.<tool>`); not
part of the installed distribution, and never imported by the packages it installs."""
