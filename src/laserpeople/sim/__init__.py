"""laserpeople.sim"""
