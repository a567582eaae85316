"""TODO farm"""
