textures/x
{
	{
		map textures/x.tga
