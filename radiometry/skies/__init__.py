"""Sky models and environment maps: CIE standard general skies, Perez all-weather skies, sky patches (Tregenza, Reinhart MF:m), equirectangular environments."""
