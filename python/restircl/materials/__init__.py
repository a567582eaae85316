"""TODO materials"""
