// a comment
textures/a/b
{
	qer_editorimage textures/a/b.tga
	surfaceparm nomarks
	{
		map $lightmap
		rgbGen identity
	}
	{
		clampMap textures/a/b.jpg
		blendFunc GL_DST_COLOR GL_ZERO
	}
}

/* block
 comment */ "textures/quoted name" { { animMap 8 textures/f1.tga textures/f2.tga } }
textures/sky { skyParms full 512 - { map textures/skies/clouds.tga tcMod scroll 0.1 0.1 } }
