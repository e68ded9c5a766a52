"""The scene read as Cycles renders it, into pure data: the scene capture and its cache, the world, lights and luminaires, shader kinds, thin glass and media."""
