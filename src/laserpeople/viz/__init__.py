"""laserpeople.viz"""
