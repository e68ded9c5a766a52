"""The sun and the weather: the NREL Solar Position Algorithm and its tables, EnergyPlus weather files."""
