"""Built-in demo scene, built by code (no binary .blend in the repository)."""
