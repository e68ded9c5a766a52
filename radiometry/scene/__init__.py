"""The scene as pure data: the scene model, closed-form geometry, exact visibility, thin glass and media."""
